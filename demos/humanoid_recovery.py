"""Demo ``humanoid-recovery``: the seed's Figs. 6 and 7 in simulation.

The humanoid balances on its right leg until an actuator enters the 75 degC
warning zone, then recovers (every actuator below 70 degC) with (a) the
thermal-aware choice of contact mode and configuration (Eq. 33, planned with
models identified from its own calibration log) and (b) minimum effort.
Plots: temperature norms of the left leg, right leg and torso, the hot leg's
cooling rate (0.1 Hz low-pass derivative, as Fig. 7), the contact mode over
time, and offscreen renders of the chosen configurations.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from humanoid_pb.actuators import datasheet_bank, effort_limits
from humanoid_pb.calibration import calibrate
from humanoid_pb.constants import ACTUATORS, TORSO_ACTUATORS, leg_actuators
from humanoid_pb.fast_ik import FastThermalIK
from humanoid_pb.params import RECOVERED_C, VALKYRIE, WARNING_C
from humanoid_pb.poses import crouch_angles, single_support, standing
from humanoid_pb.potential import MinimumEffort
from humanoid_pb.recovery import cooling_bound, run_recovery, steady_needed_for_ratio
from humanoid_pb.sim import HumanoidSim
from humanoid_pb.statics import WholeBody
from thermolimb.demo_registry import DemoPage, demo_main, register_demo
from thermolimb.identification.regression import lowpass
from thermolimb.plotting.fits import plt, save

NAME = "humanoid-recovery"
STRATEGIES = ("thermal_aware", "minimum_effort")
GROUPS = {"left leg": leg_actuators("left"), "right leg": leg_actuators("right"), "torso": TORSO_ACTUATORS}


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    ta, me = summary["thermal_aware"], summary["minimum_effort"]

    def seconds(v):
        return "not reached" if v is None else f"{v:.1f} s"

    ratio = (me["hot_leg_recovery_s"] / ta["hot_leg_recovery_s"]
             if ta["hot_leg_recovery_s"] and me["hot_leg_recovery_s"] else None)
    return [("hot leg below 70 °C, thermal-aware", seconds(ta["hot_leg_recovery_s"]),
             f"minimum effort {seconds(me['hot_leg_recovery_s'])}"
             + (f" ({ratio:.2f}× as long)" if ratio else "")),
            ("hot leg's fastest cooling, thermal-aware", f"{ta['hot_leg_peak_cooling_rate_K_s']:.2f} K/s",
             f"minimum effort {me['hot_leg_peak_cooling_rate_K_s']:.2f} K/s"),
            ("contact modes chosen", ", ".join(ta["modes_chosen"]), "minimum effort: " + ", ".join(me["modes_chosen"])),
            ("fell", f"thermal-aware {ta['fell']}, minimum effort {me['fell']}", "the robot must never fall")] + _bound_rows(summary)


def _bound_rows(summary: dict) -> list[tuple[str, str, str]]:
    bound = summary["details"]["first_order"]
    hot = bound["hot_actuator"]
    rows = [(f"{hot} held {name}: steady temperature, first-order 75 → 70 °C", f"{b['steady_C']:.1f} °C",
             f"{b['warning_to_recovered_s']:.1f} s at {b['effort_fraction']:.1%} of its limit")
            for name, b in bound["configurations"].items()]
    rows.append(("double support would need, for the seed's 2×", f"{bound['double_steady_needed_for_2x_C']:.1f} °C",
                 "steady temperature of the hot actuator, held in double support"))
    return rows


PAGE = DemoPage(
    about="The seed's recovery experiment on the humanoid: balancing heats the stance leg to the 75 °C warning, "
          "then each strategy recovers until every actuator is below 70 °C, thermal-aware contact switching "
          "against minimum effort. Look at the hot leg's time to 70 °C and cooling rate, and at the contact "
          "modes each strategy chose.",
    headline=_headline,
    captions={"temperature_norms.png": "Top: the norm of each group's temperatures over time, one panel per "
                                       "strategy (dotted: the warning). Bottom left: the robot's hottest actuator, "
                                       "with the warning (75 °C) and the recovery threshold (70 °C) dashed. "
                                       "Bottom right: the hot leg's cooling rate after the warning.",
              "contact_modes.png": "Contact mode chosen over time by each strategy.",
              "configuration_": "The configuration the strategy holds in that contact mode."})


@register_demo(NAME, "humanoid thermal recovery: thermal-aware contact switching against minimum effort",
               page=PAGE)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    bank, _ = calibrate(90.0 if quick else 180.0, quiet=quiet)
    limit_s = 90.0 if quick else 240.0
    runs = {s: run_recovery(s, bank, max_heat_s=limit_s, max_recovery_s=limit_s, quiet=quiet) for s in STRATEGIES}
    summary = {s: runs[s].summary() for s in STRATEGIES}
    rates = {}
    for s, r in runs.items():
        t, norm = _norm(r, "right leg")
        rate = np.gradient(lowpass(norm, 0.1, t[1] - t[0]), t)
        after = t >= (r.warning_at_s or t[-1])
        rates[s] = float(np.min(rate[after])) if after.any() else None
        summary[s]["hot_leg_peak_cooling_rate_K_s"] = rates[s]
    _plot_norms(runs, out / "temperature_norms.png")
    _plot_modes(runs, out / "contact_modes.png")
    _render(runs, out)
    summary["details"] = {"identified_RC_s_median": float(np.median(bank.RC_s)),
                          "first_order": _first_order(runs["thermal_aware"])}
    return summary


def _first_order(run) -> dict:
    """The physics behind the two times: where each recovery configuration holds the hottest actuator, by Eq. 23
    and the plant's winding node (the datasheet models), and how fast a first-order winding cools there."""
    body = WholeBody()
    T = np.array(run.temperature_C)
    at_warning = T[np.searchsorted(run.time_s, run.warning_at_s)] if run.warning_at_s is not None else T[-1]
    hot = ACTUATORS[int(np.argmax(at_warning))]
    q = standing(body, crouch_angles())
    cost = MinimumEffort(effort_limits(VALKYRIE))
    solver = FastThermalIK(body)
    held = {"double support, minimum effort": ("double", solver.solve(q, "double", cost, max_iter=15).q),
            "on the cool (left) foot": ("left", single_support(body, q, "left"))}
    bound = cooling_bound(body, datasheet_bank(VALKYRIE), hot, held)
    fastest = min(b["steady_C"] for b in bound.values())
    return {"hot_actuator": hot, "configurations": bound,
            "double_steady_needed_for_2x_C": steady_needed_for_ratio(2.0, fastest)}


def _norm(run, group):
    t = np.array(run.time_s)
    T = np.array(run.temperature_C)
    idx = [ACTUATORS.index(a) for a in GROUPS[group]]
    return t, np.linalg.norm(T[:, idx], axis=1)


def _plot_norms(runs, path):
    """Fig. 6/7 of the seed: each group's temperature norm per strategy (top), the hottest actuator against the
    warning and recovery thresholds and the hot leg's cooling rate (bottom)."""
    fig, axes = plt.subplots(2, 2, figsize=(13, 7.5))
    hottest, rate = axes[1, 0], axes[1, 1]
    for k, (s, r) in enumerate(runs.items()):
        for group in GROUPS:
            t, norm = _norm(r, group)
            axes[0, k].plot(t, norm, label=group)
        t, norm = _norm(r, "right leg")
        words = s.replace("_", " ")
        hottest.plot(t, np.max(np.array(r.temperature_C), axis=1), label=words)
        rate.plot(t - (r.warning_at_s or 0.0), np.gradient(lowpass(norm, 0.1, t[1] - t[0]), t), label=words)
    for ax, (s, r) in zip(axes[0], runs.items()):
        ax.set_title(f"{s.replace('_', ' ')}: temperature norms")
        ax.set_xlabel("time (s)")
        ax.set_ylabel("norm of the group's temperatures (°C)")
        if r.warning_at_s:
            ax.axvline(r.warning_at_s, color="k", ls=":", lw=0.8)
        ax.legend(fontsize=8)
    hottest.axhline(WARNING_C, color="tab:red", ls="--", lw=1, label=f"warning, {WARNING_C:.0f} °C")
    hottest.axhline(RECOVERED_C, color="tab:green", ls="--", lw=1, label=f"recovered, {RECOVERED_C:.0f} °C")
    hottest.set_title("hottest actuator of the robot")
    hottest.set_xlabel("time (s)")
    hottest.set_ylabel("temperature (°C)")
    rate.set_title("hot (right) leg: rate of its norm, 0.1 Hz low-pass")
    rate.set_xlabel("time since the warning (s)")
    rate.set_ylabel("rate (K/s)")
    hottest.legend(fontsize=8)
    rate.legend(fontsize=8)
    fig.tight_layout()
    save(fig, path)


def _plot_modes(runs, path):
    fig, ax = plt.subplots(figsize=(10, 2.8))
    code = {"double": 0, "left": 1, "right": -1}
    for k, (s, r) in enumerate(runs.items()):
        ax.step(r.time_s, [code[m] + 0.05 * k for m in r.modes], where="post", label=s)
    ax.set_yticks([-1, 0, 1], ["right support", "double support", "left support"])
    ax.set_xlabel("time (s)")
    ax.set_title("contact mode over time")
    ax.legend(fontsize=8)
    save(fig, path)


def _render(runs, out):
    for s, r in runs.items():
        for mode, angles in r.configurations.items():
            with HumanoidSim(angles if mode == "double" else crouch_angles()) as sim:
                if mode != "double":
                    sim.set_joint_positions(angles)
                image = sim.render()
            fig, ax = plt.subplots(figsize=(4, 4))
            ax.imshow(image)
            ax.set_axis_off()
            ax.set_title(f"{s}: chosen {mode}-support configuration", fontsize=9)
            save(fig, out / f"configuration_{s}_{mode}.png")


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()

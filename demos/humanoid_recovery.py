"""Demo ``humanoid-recovery``: Jorgensen et al.'s Figs. 6 and 7 in simulation, in each scenario of
:mod:`humanoid_pb.scenarios`.

The humanoid balances on its right leg until an actuator enters the 75 degC
warning zone, then recovers (every actuator below 70 degC) with (a) the
thermal-aware choice of contact mode and configuration (Eq. 33, planned with
models identified from its own calibration log) and (b) minimum effort.
Plots in Jorgensen et al.'s layout: Fig. 6 (the temperature norms of the left leg,
right leg and torso over the contact-mode sequence, per strategy), Fig. 7 (the
hot leg's norm rate, 0.1 Hz low-pass derivative, both strategies aligned at the
warning), and offscreen renders of the chosen configurations.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from humanoid_pb.calibration import calibrate
from humanoid_pb.constants import ACTUATORS, TORSO_ACTUATORS, leg_actuators
from humanoid_pb.experiments.recovery import cooling_bound, run_recovery, steady_needed_for_ratio
from humanoid_pb.ik.fast_ik import FastThermalIK
from humanoid_pb.ik.poses import crouch_angles, single_support, standing
from humanoid_pb.ik.potential import MinimumEffort
from humanoid_pb.limits import LIMITS
from humanoid_pb.model.actuation import effort_limits
from humanoid_pb.model.statics import WholeBody
from humanoid_pb.params import VALKYRIE
from humanoid_pb.scenarios import SCENARIOS, scenario
from humanoid_pb.sim import HumanoidSim
from humanoid_pb.thermal import datasheet_bank
from thermolimb.demo_registry import DemoPage, demo_main, register_demo, seconds, yes_no
from thermolimb.identification.regression import lowpass
from thermolimb.plotting.fits import plt, save

NAME = "humanoid-recovery"
STRATEGIES = ("thermal_aware", "minimum_effort")
GROUPS = {"left leg": leg_actuators("left"), "right leg": leg_actuators("right"), "torso": TORSO_ACTUATORS}
QUICK_SCENARIOS = ("walking",)  # the quick run: the stance knee, as on Valkyrie
HOT_LEG = "right leg"  # the robot balances on its right leg before the warning


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    rows = []
    for name in (n for n in SCENARIOS if n in summary):
        ta, me = summary[name]["thermal_aware"], summary[name]["minimum_effort"]
        ratio = (me["hot_leg_recovery_s"] / ta["hot_leg_recovery_s"]
                 if ta["hot_leg_recovery_s"] and me["hot_leg_recovery_s"] else None)
        rows += [(f"{name}: hot leg below 70 °C, thermal-aware", seconds(ta["hot_leg_recovery_s"]),
                  f"minimum effort {seconds(me['hot_leg_recovery_s'])}"
                  + (f" ({ratio:.2f}× as long)" if ratio else "")),
                 (f"{name}: every actuator below 70 °C, thermal-aware", seconds(ta["recovery_s"]),
                  f"minimum effort {seconds(me['recovery_s'])}"),
                 (f"{name}: contact modes chosen", ", ".join(ta["modes_chosen"]) or "none",
                  "minimum effort: " + (", ".join(me["modes_chosen"]) or "none")),
                 (f"{name}: fell", f"thermal-aware: {yes_no(ta['fell'])}, minimum effort: {yes_no(me['fell'])}",
                  "the robot must never fall")]
        rows += _bound_rows(name, summary["details"][name]["first_order"])
    return rows


def _bound_rows(name: str, bound: dict) -> list[tuple[str, str, str]]:
    hot = bound["hot_actuator"]
    rows = [(f"{name}: {hot} held {held}: steady temperature, first-order 75 → 70 °C", f"{b['steady_C']:.1f} °C",
             f"{b['warning_to_recovered_s']:.1f} s at {b['effort_fraction']:.1%} of its limit")
            for held, b in bound["configurations"].items()]
    rows.append((f"{name}: double support would need, for Jorgensen et al.'s 2×",
                 f"{bound['double_steady_needed_for_2x_C']:.1f} °C",
                 "steady temperature of the hot actuator, held in double support"))
    return rows


def _finding(summary: dict) -> str:
    parts, benefit = [], False
    for name in (n for n in SCENARIOS if n in summary):
        ta, me = summary[name]["thermal_aware"]["hot_leg_recovery_s"], summary[name]["minimum_effort"]["hot_leg_recovery_s"]
        benefit |= ta is not None and (me is None or me > 1.1 * ta)
        parts.append(f"in the {name} scenario the hot leg is below 70 °C after {seconds(ta)} thermal-aware against "
                     f"{seconds(me)} with minimum effort")
    text = "In this run " + "; ".join(parts)
    if benefit:
        return text + "."
    held = [b["steady_C"] for name in summary if name in SCENARIOS
            for b in summary["details"][name]["first_order"]["configurations"].values()]
    return (text + ": no benefit, because every mode it could switch to leaves the hot actuator cooling towards "
            f"nearly the same steady temperature ({min(held):.1f} to {max(held):.1f} °C, rows below). Switching pays "
            "where one mode unloads the hot group far more than the others: see humanoid-switching-map's hip-pitch "
            "cells.")


PAGE = DemoPage(
    about="Jorgensen et al.'s recovery experiment on the humanoid, in two scenarios (humanoid_pb/scenarios.py): 'ankle', "
          "the crouch where the stance ankle's push rods run hottest and double support unloads them, and "
          "'walking', bent knees near walking height where the stance knee runs hottest and stays loaded in "
          "double support, as on Valkyrie. Balancing on the right leg heats it to the 75 °C warning; then each "
          "strategy recovers until every actuator is below 70 °C, thermal-aware contact switching against "
          "minimum effort, from the same warning state. Look at the hot leg's time to 70 °C, its cooling rate, "
          "and the contact modes each strategy chose.",
    headline=_headline,
    finding=_finding,
    captions={"fig6_": "Jorgensen et al.'s Fig. 6 for one scenario: for each strategy, (e) the norms of the left leg's, "
                       "right leg's and torso's actuator temperatures against the time since the warning (vertical "
                       "lines: the warning, then the hot leg's and every actuator's recovery, as the legend says), "
                       "and (f) the contact mode under it, on the same time axis.",
              "fig7_": "Jorgensen et al.'s Fig. 7 for one scenario: (a) the hot (right) leg's norm rate, 0.1 Hz low-pass "
                       "derivative, both strategies aligned at the warning, with each one's hot-leg-safe time "
                       "marked; (b) the hottest actuator against the warning (75 °C) and recovery (70 °C) lines.",
              "configuration_": "The configuration the strategy holds in that contact mode."})


@register_demo(NAME, "humanoid thermal recovery: thermal-aware contact switching against minimum effort",
               page=PAGE, cost_s=40)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    limit_s = 120.0 if quick else 240.0  # Jorgensen et al.: the warning "in less than two minutes"
    summary, details = {}, {}
    for name in QUICK_SCENARIOS if quick else SCENARIOS:
        bank = calibrate(90.0 if quick else 180.0, quiet=quiet, scenario=name).bank
        runs = {s: run_recovery(s, bank, max_heat_s=limit_s, max_recovery_s=limit_s, quiet=quiet, scenario=name)
                for s in STRATEGIES}
        summary[name] = {s: runs[s].summary() for s in STRATEGIES}
        for s, r in runs.items():
            t, rate = _norm_rate(r)
            after = t >= 0.0
            summary[name][s]["hot_leg_peak_cooling_rate_K_s"] = float(np.min(rate[after])) if after.any() else None
        _plot_fig6(runs, name, out / f"fig6_{name}.png")
        _plot_fig7(runs, name, out / f"fig7_{name}.png")
        _render(runs, name, out)
        details[name] = {"identified_RC_s_median": float(np.median(bank.RC_s)),
                         "first_order": _first_order(runs["thermal_aware"], name)}
    summary["details"] = details
    return summary


def _first_order(run, name: str) -> dict:
    """The physics behind the two times: where each recovery configuration holds the hottest actuator, by Eq. 23
    and the plant's winding node (the datasheet models), and how fast a first-order winding cools there."""
    stance = scenario(name)
    body = WholeBody()
    T = np.array(run.temperature_C)
    at_warning = T[np.searchsorted(run.time_s, run.warning_at_s)] if run.warning_at_s is not None else T[-1]
    hot = ACTUATORS[int(np.argmax(at_warning))]
    q = standing(body, crouch_angles(stance.crouch_depth_rad))
    cost = MinimumEffort(effort_limits(VALKYRIE))
    solver = FastThermalIK(body)
    held = {"double support, minimum effort": ("double", solver.solve(q, "double", cost, max_iter=15).q),
            "on the cool (left) foot": ("left", single_support(body, q, "left"))}
    bound = cooling_bound(body, datasheet_bank(VALKYRIE, scenario=stance), hot, held)
    fastest = min(b["steady_C"] for b in bound.values())
    return {"hot_actuator": hot, "configurations": bound,
            "double_steady_needed_for_2x_C": steady_needed_for_ratio(2.0, fastest)}


def _norm(run, group):
    t = np.array(run.time_s)
    T = np.array(run.temperature_C)
    idx = [ACTUATORS.index(a) for a in GROUPS[group]]
    return t, np.linalg.norm(T[:, idx], axis=1)


def _norm_rate(run):
    """The hot leg's norm rate (K/s; 0.1 Hz low-pass derivative, as Jorgensen et al.'s Fig. 7) against the time since the
    warning (s)."""
    t, norm = _norm(run, HOT_LEG)
    rate = np.gradient(lowpass(norm, 0.1, t[1] - t[0]), t)
    return t - (run.warning_at_s if run.warning_at_s is not None else t[-1]), rate


def _marks(ax, run):
    """The warning, the hot leg's recovery and every actuator's, as vertical lines on a time-since-warning axis."""
    zero = run.warning_at_s if run.warning_at_s is not None else 0.0
    for value, style, label in ((run.warning_at_s, ":", "75 °C reached"),
                                (_after(run, run.hot_leg_recovery_s), "--", "hot leg < 70 °C"),
                                (_after(run, run.recovery_s), "-", "all < 70 °C")):
        if value is not None:
            ax.axvline(value - zero, color="k", ls=style, lw=0.8, label=label)


def _after(run, delay_s):
    return None if delay_s is None or run.warning_at_s is None else run.warning_at_s + delay_s


def _plot_fig6(runs, name, path):
    """Jorgensen et al.'s Fig. 6 (e) and (f), one column per strategy: group norms over the mode sequence."""
    fig, axes = plt.subplots(2, len(runs), figsize=(5.5 * len(runs), 6.5), sharex="col",
                             gridspec_kw={"height_ratios": [3, 1]})
    code = {"right": 0, "double": 1, "left": 2}
    for k, (s, r) in enumerate(runs.items()):
        zero = r.warning_at_s or 0.0
        norms, modes = axes[0, k], axes[1, k]
        for group in GROUPS:
            t, norm = _norm(r, group)
            norms.plot(t - zero, norm, label=group)
        _marks(norms, r)
        norms.set_title(f"{name}, {s.replace('_', ' ')}: (e) temperature norms")
        norms.set_ylabel("norm of the group's temperatures (°C)")
        norms.legend(fontsize=7)
        modes.step(np.array(r.time_s) - zero, [code[m] for m in r.modes], where="post", color="tab:purple")
        _marks(modes, r)
        modes.set_yticks([0, 1, 2], ["right", "double", "left"])
        modes.set_ylim(-0.5, 2.5)
        modes.set_title("(f) contact mode", fontsize=9)
        modes.set_xlabel("time since the warning (s)")
    fig.tight_layout()
    save(fig, path)


def _plot_fig7(runs, name, path):
    """Jorgensen et al.'s Fig. 7 (a): the hot leg's norm rate, both strategies aligned at the warning; (b) the hottest
    actuator against the thresholds."""
    fig, (rate_ax, hottest) = plt.subplots(1, 2, figsize=(11, 4))
    for s, r in runs.items():
        words = s.replace("_", " ")
        t, rate = _norm_rate(r)
        line, = rate_ax.plot(t, rate, label=words)
        if r.hot_leg_recovery_s is not None:
            rate_ax.axvline(r.hot_leg_recovery_s, color=line.get_color(), ls="--", lw=0.8,
                            label=f"{words}: hot leg < 70 °C at {r.hot_leg_recovery_s:.1f} s")
        zero = r.warning_at_s or 0.0
        hottest.plot(np.array(r.time_s) - zero, np.max(np.array(r.temperature_C), axis=1), label=words)
    rate_ax.set_title(f"{name}: (a) hot (right) leg's norm rate, 0.1 Hz low-pass")
    rate_ax.set_xlabel("time since the warning (s)")
    rate_ax.set_ylabel("rate (K/s)")
    rate_ax.set_xlim(left=-10.0)
    hottest.axhline(LIMITS.warning_C, color="tab:red", ls="--", lw=1, label=f"warning, {LIMITS.warning_C:.0f} °C")
    hottest.axhline(LIMITS.recovered_C, color="tab:green", ls="--", lw=1, label=f"recovered, {LIMITS.recovered_C:.0f} °C")
    hottest.set_title(f"{name}: (b) hottest actuator of the robot")
    hottest.set_xlabel("time since the warning (s)")
    hottest.set_ylabel("temperature (°C)")
    rate_ax.legend(fontsize=7)
    hottest.legend(fontsize=7)
    fig.tight_layout()
    save(fig, path)


def _render(runs, name, out):
    for s, r in runs.items():
        for mode, angles in r.configurations.items():
            with HumanoidSim(angles if mode == "double" else None, scenario=name) as sim:
                if mode != "double":
                    sim.set_joint_positions(angles)
                image = sim.render()
            fig, ax = plt.subplots(figsize=(4, 4))
            ax.imshow(image)
            ax.set_axis_off()
            ax.set_title(f"{name}, {s}: chosen {mode}-support configuration", fontsize=9)
            save(fig, out / f"configuration_{name}_{s}_{mode}.png")


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()

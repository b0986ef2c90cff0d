"""Demo ``hexapod-walk``: Nair et al.'s three load-carrying scenarios with four stance-force strategies.

Walking with no load, walking with 2 kg, standing with 5 kg; vertical-only
forces (HEBI's stock controller), the minimax of the peak normalised torque
(Nair et al.), minimax with a least-squares second stage, and the thermal-aware
distribution.  Torques per leg and joint over one stride, per-scenario bars,
temperature traces of a long carry, and ``summary.json``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from hexapod_pb.constants import JOINT_KINDS, LEGS
from hexapod_pb.control.wrench import STRATEGIES
from hexapod_pb.experiments.load_carrying import SCENARIOS, run_scenario
from thermolimb.demo_registry import DemoPage, demo_main, register_demo
from thermolimb.plotting.fits import plt, save

NAME = "hexapod-walk"


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    rows = []
    for scenario, label in (("walk_0kg", "walking, no load"), ("walk_2kg", "walking with 2 kg"),
                            ("stand_5kg", "standing with 5 kg")):
        per = summary[scenario]
        rows.append((f"{label}: peak normalised torque",
                     " · ".join(f"{k.replace('_', ' ')} {v['peak_norm_torque']:.3f}" for k, v in per.items()),
                     "lower leaves more margin before the torque limit"))
        rows.append((f"{label}: hottest winding",
                     " · ".join(f"{k.replace('_', ' ')} {v['max_temperature_C']:.1f} °C" for k, v in per.items()),
                     "limit 155 °C"))
    return rows


def _finding(summary: dict) -> str:
    per = summary["walk_2kg"]
    hottest = max(v["max_temperature_C"] for s in ("walk_0kg", "walk_2kg", "stand_5kg") for v in summary[s].values())
    return (f"In this run Nair et al.'s minimax lowers the peak normalised torque walking with 2 kg to "
            f"{per['minimax']['peak_norm_torque']:.3f}, against {per['vertical_only']['peak_norm_torque']:.3f} with "
            f"vertical forces only; no winding passes {hottest:.1f} °C (limit 155 °C), so these carries have no "
            f"thermal effect to show: hexapod-endurance does.")


PAGE = DemoPage(
    about="The hexapod walking with no load and with 2 kg, and standing with 5 kg, under four ways of sharing "
          "the stance forces: vertical forces only, Nair et al.'s minimax of normalised torque, minimax with a "
          "second stage, and thermal-aware. Look at the peak normalised torque (Nair et al.'s objective) and at the "
          "temperatures: in these scenarios the windings stay far below their limit, so no strategy has a "
          "thermal effect to show here.",
    headline=_headline,
    finding=_finding,
    captions={"torques_one_stride_walk_2kg.png": "Normalised joint torques over one stride with 2 kg, per strategy.",
              "peak_and_mean_by_scenario.png": "Peak and mean normalised torque per scenario and strategy.",
              "temperatures.png": "Hottest winding temperature over the carry, per strategy."})


@register_demo(NAME, "hexapod carrying loads: torques, peaks and means per strategy, temperatures over a long carry",
               page=PAGE, cost_s=19)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    duration = 15.0 if quick else 1200.0  # the long carry: 20 minutes
    results = {(s, k): run_scenario(s, k, duration, quiet=quiet) for s in SCENARIOS for k in STRATEGIES}
    summary = {s: {k: results[s, k].summary() for k in STRATEGIES} for s in SCENARIOS}
    _plot_stride(results, out / "torques_one_stride_walk_2kg.png")
    _plot_bars(summary, out / "peak_and_mean_by_scenario.png")
    _plot_temperatures(results, out / "temperatures.png")
    walk = summary["walk_2kg"]
    summary["details"] = {
        "walk_2kg_peak_reduction_minimax_vs_vertical": 1 - walk["minimax"]["peak_norm_torque"]
        / walk["vertical_only"]["peak_norm_torque"],
        "walk_2kg_mean_change_minimax_vs_vertical": walk["minimax"]["mean_norm_torque"]
        / walk["vertical_only"]["mean_norm_torque"] - 1,
        "duration_s": duration,
    }
    return summary


def _plot_stride(results, path):
    fig, axes = plt.subplots(len(JOINT_KINDS), 2, figsize=(12, 8), sharex=True, sharey="row")
    for col, strategy in enumerate(("vertical_only", "minimax")):
        r = results["walk_2kg", strategy]
        k = r.stride_steps
        window = slice(len(r.time_s) - k, len(r.time_s))
        t = r.time_s[window] - r.time_s[window][0]
        for row, kind in enumerate(JOINT_KINDS):
            ax = axes[row, col]
            for leg_i, leg in enumerate(LEGS):
                ax.plot(t, r.norm_commanded[window, 3 * leg_i + row], lw=1, label=leg)
            ax.axhline(1.0, color="k", ls=":", lw=0.8)
            ax.set_title(f"{strategy}: {kind} joints, walking with 2 kg", fontsize=9)
            ax.set_ylabel("|τ| / τ_cont")
        axes[-1, col].set_xlabel("time in the stride (s)")
    axes[0, 0].legend(fontsize=7, ncol=2)
    save(fig, path)


def _plot_bars(summary, path):
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    x = np.arange(len(SCENARIOS))
    width = 0.2
    for i, strategy in enumerate(STRATEGIES):
        for ax, key in zip(axes, ("peak_norm_torque", "mean_norm_torque")):
            ax.bar(x + (i - 1.5) * width, [summary[s][strategy][key] for s in SCENARIOS], width, label=strategy)
    for ax, title in zip(axes, ("peak normalised torque per stride", "mean normalised torque")):
        ax.set_xticks(x, list(SCENARIOS))
        ax.set_title(title)
    axes[0].legend(fontsize=8)
    save(fig, path)


def _plot_temperatures(results, path):
    fig, axes = plt.subplots(1, len(SCENARIOS), figsize=(14, 4), sharey=True)
    for ax, scenario in zip(axes, SCENARIOS):
        for strategy in STRATEGIES:
            r = results[scenario, strategy]
            ax.plot(r.time_s / 60.0, r.measured_C.max(axis=1), lw=1, label=strategy)
        ax.set_title(f"{scenario}: hottest winding (measured)")
        ax.set_xlabel("time (min)")
    axes[0].set_ylabel("°C")
    axes[0].legend(fontsize=8)
    save(fig, path)


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()

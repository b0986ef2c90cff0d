"""Demo ``hexapod-endurance``: how long until the first actuator derates, across payload, ambient and strategy.

Every cell is measured in PyBullet and propagated over hours through the
plant's exact cycle map (:mod:`hexapod_pb.endurance`); the thermal-aware
strategies plan with models identified from the robot's own calibration log.
One cell is also run whole in PyBullet (20 minutes; 40 s in ``--quick``) and the
propagation compared with it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from hexapod_pb.calibration import at_ambient, calibrate
from hexapod_pb.experiments.endurance import (
    GAIT_CHOICES,
    MODES,
    STRATEGIES,
    check_periodic,
    derating_threshold_C,
    endurance,
    plan_gait,
)
from thermolimb.demo_registry import DemoPage, demo_main, register_demo
from thermolimb.plotting.fits import plt, save

NAME = "hexapod-endurance"
FULL = {"payloads_kg": (0.0, 20.0, 25.0, 30.0, 40.0, 60.0, 80.0, 100.0), "ambients_C": (25.0, 40.0),
        "horizon_s": 8 * 3600.0, "window_s": 3600.0, "calibration_s": 1200.0, "check_s": 1200.0,
        "choices": GAIT_CHOICES}
# the quick run: one payload per mode where the strategies part (walking 25 kg: vertical-only derates within the
# horizon, the others not; standing 80 kg: every strategy derates, at times an order of magnitude apart)
QUICK = {"payloads_kg": {"walk": (25.0,), "stand": (80.0,)}, "ambients_C": (40.0,), "horizon_s": 8 * 3600.0,
         "window_s": 4 * 3600.0, "calibration_s": 90.0, "check_s": 40.0,
         "choices": {"duty_factor": (0.55,), "foot_reach_m": (0.16,), "body_height_m": (0.13,),
                     "pause_share": (0.0, 0.1)}}
CHECK_CELL = {"payload_kg": 20.0, "ambient_C": 40.0, "mode": "walk", "strategy": "vertical_only"}
BASELINE = "vertical_only"
FLOOR_H = 1.0 / 60.0  # where the figure marks loads the robot cannot carry


def payloads(grid: dict, mode: str) -> tuple:
    """The grid's payloads (kg) for ``mode``: one tuple for every mode, or one per mode."""
    given = grid["payloads_kg"]
    return given[mode] if isinstance(given, dict) else given


def best_gain(cells: list[dict]) -> dict | None:
    """Among cells where vertical-only derates within the horizon, the thermal-aware cell that buys the most time
    while keeping at least 80 % of vertical-only's distance per second (standing: no distance to keep)."""
    by_key = {(c["payload_kg"], c["ambient_C"], c["mode"], c["strategy"]): c for c in cells}
    best = None
    for c in cells:
        if c["strategy"] not in ("thermal_aware", "thermal_gait") or c["fell"] or not c["holds_heading"]:
            continue
        base = by_key.get((c["payload_kg"], c["ambient_C"], c["mode"], BASELINE))
        if base is None or base["fell"] or not base["holds_heading"] or base["time_to_derate_s"] is None:
            continue
        if c["distance_per_s_m"] < 0.8 * base["distance_per_s_m"]:
            continue
        time = c["time_to_derate_s"] if c["time_to_derate_s"] is not None else c["horizon_s"]
        gain = time / base["time_to_derate_s"]
        never = c["time_to_derate_s"] is None and c["steady_hottest_C"] < c["threshold_C"]
        row = {"payload_kg": c["payload_kg"], "ambient_C": c["ambient_C"], "mode": c["mode"], "strategy": c["strategy"],
               "vertical_only_s": base["time_to_derate_s"], "strategy_s": c["time_to_derate_s"],
               "at_least_ratio": gain, "never_derates": never, "steady_hottest_C": c["steady_hottest_C"],
               "distance_share": (c["distance_per_s_m"] / base["distance_per_s_m"]
                                  if base["distance_per_s_m"] > 0 else None)}
        # prefer a cell that never derates, then the longest time, then the coolest steady state
        if best is None or (never, gain, -c["steady_hottest_C"]) > (best["never_derates"], best["at_least_ratio"],
                                                                    -best["steady_hottest_C"]):
            best = row
    return best


def _fmt_time(seconds) -> str:
    if seconds is None:
        return "none within the horizon"
    return f"{seconds:.0f} s" if seconds < 120.0 else f"{seconds / 60:.0f} min"


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    details = summary.get("details", {})
    rows = []
    for key, label in (("best_walking", "walking"), ("best_standing", "standing")):
        best = details.get(key)
        if best:
            rows.append((f"largest gain {label} ({best['payload_kg']:.0f} kg, {best['ambient_C']:.0f} °C)",
                         f"{best['strategy']}: {_fmt_time(best['strategy_s'])}, at least {best['at_least_ratio']:.1f}×"
                         + (f" (never: it settles at {best['steady_hottest_C']:.0f} °C)" if best["never_derates"] else ""),
                         f"vertical-only derates after {_fmt_time(best['vertical_only_s'])}"))
    check = details.get("periodic_check")
    if check:
        rows.append(("propagation against a whole PyBullet run",
                     f"{check['max_abs_difference_K']:.2g} K at most, {check['final_difference_K']:+.2g} K at the end",
                     f"{_fmt_time(check['duration_s'])}, hottest winding averaged per cycle"))
    return rows


def _finding(summary: dict) -> str:
    parts = []
    for key, label in (("best_walking", "walking"), ("best_standing", "standing")):
        best = summary["details"].get(key)
        if best:
            horizon_h = summary["cells"][0]["horizon_s"] / 3600
            then = (f"after {_fmt_time(best['strategy_s'])}" if best["strategy_s"] is not None
                    else f"not within the {horizon_h:.0f} h horizon")
            parts.append(f"{label} with {best['payload_kg']:.0f} kg at {best['ambient_C']:.0f} °C vertical-only "
                         f"forces derate after {_fmt_time(best['vertical_only_s'])}, "
                         f"{best['strategy'].replace('_', ' ')} {then}")
    if not parts:
        return "In this run no cell derates within the horizon under vertical-only forces: nothing to gain here."
    return "In this run " + "; ".join(parts) + "."


PAGE = DemoPage(
    about="Time until the first actuator derates (its winding 15 K below the 155 °C limit) for the hexapod "
          "walking or standing with a payload at each ambient of the grid (the quick run: walking with 25 kg and "
          "standing with 80 kg, at 40 °C; the full run: 0-100 kg at 25 and 40 °C), under vertical-only forces, the minimax of Nair et al. "
          "(with and without its second stage), thermal-aware forces, and thermal-aware forces on a gait planned "
          "with the identified models. Look at where vertical-only derates within the horizon, and at what each "
          "strategy does there; crosses mark payloads the robot cannot carry that way, hollow circles gaits that "
          "lose their heading (not periodic: their times are from the first strides only).",
    headline=_headline,
    finding=_finding,
    captions={"envelope.png": "Time to the first derating per payload, ambient and mode; the top of each panel is "
                              "the horizon (nothing derates).",
              "periodic_check.png": "The hottest winding (cycle mean) of a whole PyBullet run and of its first "
                                    "cycle propagated."})


@register_demo(NAME, "hexapod endurance envelope: time to the first derating by payload, ambient, mode and strategy",
               page=PAGE, cost_s=50)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    grid = QUICK if quick else FULL
    calibration = calibrate(grid["calibration_s"])
    bank, measured_ambient = calibration.bank, calibration.ambient_C
    cells, plans = [], {}
    for ambient in grid["ambients_C"]:
        models = at_ambient(bank, ambient)
        for mode in MODES:
            for payload in payloads(grid, mode):
                plan = plan_gait(payload, mode, ambient, models, choices=grid["choices"])
                plans[payload, ambient, mode] = plan
                for strategy in STRATEGIES:
                    result = endurance(payload, ambient, mode, strategy, grid["horizon_s"], bank=models,
                                       window_s=grid["window_s"],
                                       gait=plan.gait if strategy == "thermal_gait" else None)
                    cells.append({**result.row(), "threshold_C": float(derating_threshold_C().min())})
    check = check_periodic(CHECK_CELL["payload_kg"], CHECK_CELL["ambient_C"], CHECK_CELL["mode"],
                           CHECK_CELL["strategy"], grid["check_s"])
    _plot_envelope(cells, grid, out / "envelope.png")
    _plot_check(check, out / "periodic_check.png")
    summary = {"cells": [{k: c[k] for k in ("payload_kg", "ambient_C", "mode", "strategy", "time_to_derate_s",
                                            "horizon_s", "distance_per_s_m")} for c in cells]}
    walking = best_gain([c for c in cells if c["mode"] == "walk"])
    standing = best_gain([c for c in cells if c["mode"] == "stand"])
    summary["details"] = {
        "cells": cells, "best_walking": walking, "best_standing": standing,
        "periodic_check": {**CHECK_CELL, **check.summary()},
        "calibration": {"duration_s": grid["calibration_s"], "measured_ambient_C": measured_ambient,
                        "RC_s": bank.RC_s.tolist(), "betaR_K_per_Nm2": bank.betaR_K_per_effort2.tolist()},
        "gait_plans": [{"payload_kg": p, "ambient_C": a, "mode": m, "duty_factor": plan.gait.duty_factor,
                        "foot_reach_m": plan.gait.foot_reach_m, "body_height_m": plan.gait.body_height_m,
                        "pause_share": plan.gait.pause_share, "predicted_peak_C": plan.predicted_peak_C, "nominal_predicted_peak_C":
                        plan.nominal_predicted_peak_C, "candidates": plan.candidates}
                       for (p, a, m), plan in plans.items()],
    }
    return summary


def _plot_envelope(cells: list[dict], grid: dict, path: Path) -> None:
    ambients, horizon = grid["ambients_C"], grid["horizon_s"]
    fig, axes = plt.subplots(len(MODES), len(ambients), figsize=(6 * len(ambients), 7.5), squeeze=False,
                             sharex=not isinstance(grid["payloads_kg"], dict), sharey=True)
    for i, mode in enumerate(MODES):
        for j, ambient in enumerate(ambients):
            ax = axes[i, j]
            for k, strategy in enumerate(STRATEGIES):
                rows = sorted((c for c in cells if c["mode"] == mode and c["ambient_C"] == ambient
                               and c["strategy"] == strategy), key=lambda c: c["payload_kg"])
                x = np.array([c["payload_kg"] for c in rows]) + (k - 2) * 0.6
                hours = [np.nan if c["fell"] else (c["time_to_derate_s"] or horizon) / 3600 for c in rows]
                # lines only where the payload grid is fine enough to read a trend between its points
                # one colour per strategy in every panel (a marker-only plot below must not move the cycle)
                line, = ax.plot(x, hours, "o-" if len(rows) >= 4 else "o", ms=4, lw=1.2, color=f"C{k}",
                                label=strategy.replace("_", " "))
                fell = [xx for xx, c in zip(x, rows) if c["fell"]]
                ax.plot(fell, [FLOOR_H] * len(fell), "x", color=line.get_color(), ms=7)
                turning = [(xx, h) for xx, h, c in zip(x, hours, rows) if not c["fell"] and not c["holds_heading"]]
                if turning:
                    ax.plot(*zip(*turning), "o", color=line.get_color(), mfc="white", ms=7)
            ax.axhline(horizon / 3600, color="k", ls=":", lw=0.8,
                       label=f"horizon, {horizon / 3600:.0f} h: points on it never derate within it")
            ax.axhline(1.0, color="0.6", ls="--", lw=0.8, label="1 h")
            ax.set_yscale("log")
            ax.set_ylim(FLOOR_H / 1.5, horizon / 3600 * 1.5)
            ax.set_title(f"{mode}, ambient {ambient:.0f} °C (x: cannot carry it)", fontsize=10)
            ax.set_ylabel("time to first derating (h)")
            ax.set_xlabel("payload (kg)")
            ax.set_xticks(sorted(payloads(grid, mode)))  # the payloads measured; strategies side by side at each
    axes[0, 0].legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    save(fig, path)


def _plot_check(check, path: Path) -> None:
    fig, ax = plt.subplots(figsize=(8, 4))
    minutes = check.cycle_start_s / 60
    ax.plot(minutes, check.pybullet_hottest_C, lw=1, label="PyBullet, every control step")
    ax.plot(minutes, check.propagated_hottest_C, lw=1.5, label="first cycle, propagated")
    ax.set_xlabel("time (min)")
    ax.set_ylabel("hottest winding, cycle mean (°C)")
    ax.set_title(f"{CHECK_CELL['mode']} with {CHECK_CELL['payload_kg']:.0f} kg at {CHECK_CELL['ambient_C']:.0f} °C, "
                 f"{CHECK_CELL['strategy'].replace('_', ' ')}", fontsize=10)
    ax.legend(fontsize=8)
    save(fig, path)


def main(argv=None) -> dict:
    return demo_main(NAME, argv)

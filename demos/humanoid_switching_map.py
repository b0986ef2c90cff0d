"""Demo ``humanoid-switching-map``: where thermal-aware recovery beats minimum effort, over the hottest actuator
group and the stance height (:mod:`humanoid_pb.experiments.switching_map`).

Each measured cell runs Jorgensen et al.'s recovery experiment in PyBullet for a robot
whose group is the thermally weakest, in a crouch of that depth: both
strategies from the same warning state, the ratio of their hot-set-safe times
(minimum effort over thermal-aware).  The first-order prediction of every cell
is computed too; it fills the unmeasured cells between a group's measured ones
only where it meets each of that group's measured ratios within 10 %.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from humanoid_pb.experiments.switching_map import (
    AGREEMENT,
    DEPTHS_RAD,
    GROUPS,
    agreeing_groups,
    measure_cell,
    predict_cell,
)
from humanoid_pb.model.statics import WholeBody
from thermolimb.demo_registry import DemoPage, demo_main, register_demo, seconds, yes_no
from thermolimb.plotting.fits import plt, save

NAME = "humanoid-switching-map"
MEASURED_DEPTHS_RAD = (0.15, 0.3, 0.45)
QUICK_CELLS = (("knee", 0.3), ("hip pitch", 0.3))
RATIO_RANGE = 4.0  # the colour scale spans 1/4 to 4 (log scale); beyond it the cell has its end colour


def _ratio_text(cell: dict) -> str:
    if cell["ratio_at_least"] is not None:
        return f"> {cell['ratio_at_least']:.2f}"
    if cell["ratio"] is None:
        fell = [{"thermal_aware": "thermal-aware", "minimum_effort": "min. effort"}[name]
                for name, f in cell["fell"].items() if f]
        return f"{' & '.join(fell)} fell" if fell else "—"
    return "∞" if np.isinf(cell["ratio"]) else f"{cell['ratio']:.2f}"


def _headline(summary: dict) -> list[tuple[str, str, str]]:
    rows = []
    for cell in summary["measured"]:
        safe = cell["hot_set_safe_s"]
        rows.append((f"{cell['group']}, crouch {cell['depth_rad']:.2f} rad: minimum effort / thermal-aware",
                     _ratio_text(cell),
                     f"hot set below 70 °C: minimum effort {_below(safe['minimum_effort'])}, thermal-aware "
                     f"{_below(safe['thermal_aware'])}; modes chosen {', '.join(cell['modes']['thermal_aware']) or 'none'} "
                     f"/ {', '.join(cell['modes']['minimum_effort']) or 'none'}; fell: "
                     f"{yes_no(cell['fell']['thermal_aware'])} / {yes_no(cell['fell']['minimum_effort'])}"))
    for group, ok in summary["prediction_agrees"].items():
        rows.append((f"{group}: first order within {AGREEMENT:.0%} of every measured cell", "yes" if ok else "no",
                     "predictions fill the unmeasured cells between the measured ones" if ok
                     else "unmeasured cells show the prediction in parentheses, on grey: unconfirmed"))
    return rows


def _below(value) -> str:
    return "not by the end of the run" if value is None else f"after {seconds(value)}"


def _finding(summary: dict) -> str:
    cells = summary["measured"]
    faster = [c for c in cells if (c["ratio"] or c["ratio_at_least"] or 0.0) > 1.1]
    text = f"In this run thermal-aware recovery is more than 10 % faster in {len(faster)} of {len(cells)} measured cells"
    if faster:
        best = max(faster, key=lambda c: c["ratio"] or c["ratio_at_least"])
        text += f" (most for {best['group']} at {best['depth_rad']:.2f} rad: {_ratio_text(best)} times faster)"
    return text + "; the other cells are first-order predictions."


PAGE = DemoPage(
    about="When does contact switching pay? For a robot whose thermally weakest actuators are one group (ankle rods, "
          "knee, hip pitch, hip roll or torso), crouched at a depth from straight (0.15 rad) to the deepest stance the "
          "balance controller holds on one leg (0.45 rad), the map shows how many times longer minimum effort takes "
          "than the thermal-aware planner to bring the heated leg and the weak group below 70 °C after balancing on "
          "one leg to the 75 °C warning. Outlined cells were measured in PyBullet; the others are first-order "
          "predictions, shown only for groups whose measured cells they meet within 10 %.",
    headline=_headline,
    finding=_finding,
    captions={"switching_map.png": "Ratio of hot-set-safe times, minimum effort over thermal-aware (above 1: the "
                                   "thermal-aware recovery is faster), by weakest actuator group (rows) and crouch "
                                   "depth (columns; hips and ankles at minus the depth, knees at twice it). Outlined "
                                   "cells with bold numbers were measured in PyBullet; the other numbers are "
                                   "first-order predictions the measurements confirm; on grey cells, in parentheses, the "
                                   "first-order prediction where no measurement confirms it (the quick run measures "
                                   "two cells). '> x': minimum effort had not brought the hot set below 70 °C "
                                   "when the run ended, so the ratio is at least x; '∞': predicted never to.",
              "switching_prediction.png": "Measured ratio against the first-order prediction of the same cell "
                                          "(cells with a finite ratio both ways), with the band of ± 10 % "
                                          "agreement around the diagonal."})


@register_demo(NAME, "humanoid: where thermal-aware recovery beats minimum effort, by hot group and stance height",
               page=PAGE, cost_s=38)
def run(out: Path, quick: bool = False, quiet: bool = True) -> dict:
    warning_s = 40.0 if quick else 100.0  # Jorgensen et al.'s "warning in under two minutes"; quick: a shorter heating
    body = WholeBody()
    predicted = {(g, d): predict_cell(g, d, body, warning_s) for g in GROUPS for d in DEPTHS_RAD}
    cells = QUICK_CELLS if quick else [(g, d) for g in GROUPS for d in MEASURED_DEPTHS_RAD]
    measured = [measure_cell(g, d, time_to_warning_s=warning_s, max_recovery_s=30.0 if quick else 120.0,
                             quiet=quiet) for g, d in cells]
    agrees = agreeing_groups(measured, predicted)
    shown = _shown_predictions(measured, predicted, agrees)
    _plot_map(measured, shown, predicted, out / "switching_map.png")
    _plot_agreement(measured, predicted, out / "switching_prediction.png")
    return {"measured": [c.to_json() for c in measured], "prediction_agrees": agrees,
            "predicted_shown": [c.to_json() for c in shown],
            "details": {"time_to_warning_s": warning_s,
                        "predicted": [c.to_json() for c in predicted.values()]}}


def _shown_predictions(measured, predicted, agrees) -> list:
    """The predicted cells the map shows: unmeasured, between two measured depths of a group that agrees."""
    shown = []
    for group, ok in agrees.items():
        depths = sorted(c.depth_rad for c in measured if c.group == group)
        if not ok or len(depths) < 2:
            continue
        shown += [predicted[(group, d)] for d in DEPTHS_RAD if depths[0] < d < depths[-1] and d not in depths]
    return shown


def _plot_map(measured, shown, predicted, path):
    groups, depths = list(GROUPS), list(DEPTHS_RAD)
    values = np.full((len(groups), len(depths)), np.nan)
    cells = {(c.group, c.depth_rad): c for c in [*shown, *measured]}
    for (g, d), c in cells.items():
        ratio = c.ratio if c.ratio is not None else c.ratio_at_least
        if ratio is not None:
            values[groups.index(g), depths.index(d)] = np.log(min(max(ratio, 1 / RATIO_RANGE), RATIO_RANGE))
    fig, ax = plt.subplots(figsize=(9.5, 4.8))
    cmap = plt.get_cmap("RdBu_r").with_extremes(bad="0.85")
    image = ax.imshow(np.ma.masked_invalid(values), cmap=cmap, vmin=-np.log(RATIO_RANGE), vmax=np.log(RATIO_RANGE),
                      aspect="auto")
    for (g, d), c in cells.items():
        i, j = groups.index(g), depths.index(d)
        dark = abs(values[i, j]) > 0.6 * np.log(RATIO_RANGE)
        ax.text(j, i, _ratio_text(c.to_json()).replace(" fell", "\nfell"), ha="center", va="center", fontsize=9, color="w" if dark else "k",
                fontweight="bold" if c.source == "measured" else "normal",
                fontstyle="normal" if c.source == "measured" else "italic")
        if c.source == "measured":
            ax.add_patch(plt.Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, lw=2, ec="k"))
    for (g, d), c in predicted.items():  # grey cells: the first-order prediction, in parentheses, not confirmed
        if (g, d) not in cells:
            ax.text(depths.index(d), groups.index(g), f"({_ratio_text(c.to_json())})", ha="center", va="center",
                    fontsize=7, color="0.35")
    ax.set_xticks(range(len(depths)), [f"{d:.2f}" for d in depths])
    ax.set_yticks(range(len(groups)), groups)
    ax.set_xlabel("crouch depth (rad): 0.15 straightest the IK allows, 0.45 deepest held on one leg")
    ax.set_ylabel("thermally weakest group")
    ax.set_title("hot-set-safe time, minimum effort / thermal-aware (outlined: measured in PyBullet)")
    bar = fig.colorbar(image, ax=ax, ticks=np.log([0.25, 0.5, 1, 2, 4]))
    bar.ax.set_yticklabels(["1/4", "1/2", "1", "2", "4"])
    bar.set_label("ratio (log scale; above 1 thermal-aware is faster)")
    fig.tight_layout()
    save(fig, path)


def _plot_agreement(measured, predicted, path):
    fig, ax = plt.subplots(figsize=(5.5, 5))
    pairs = [(predicted[(c.group, c.depth_rad)].ratio, c.ratio, c) for c in measured]  # cells with a ratio both ways
    pairs = [(p, m, c) for p, m, c in pairs if p is not None and m is not None and np.isfinite(p) and np.isfinite(m)]
    top = max([max(p, m) for p, m, _ in pairs] + [1.5]) * 1.1
    line = np.linspace(0.0, top, 50)
    ax.plot(line, line, color="k", lw=0.8, label="prediction = measurement")
    ax.fill_between(line, line * (1 - AGREEMENT), line * (1 + AGREEMENT), color="0.85",
                    label=f"within {AGREEMENT:.0%} of the measurement")
    for p, m, c in pairs:
        ax.plot(p, m, "o")
        if abs(p - m) <= AGREEMENT * m:  # the cells inside the band crowd around 1; only the misses are named
            continue
        ax.annotate(f"{c.group}, {c.depth_rad:.2f}", (p, m), fontsize=7, xytext=(4, 4), textcoords="offset points")
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_xlabel("first-order prediction of the ratio")
    ax.set_ylabel("measured ratio (PyBullet)")
    inside = sum(abs(p - m) <= AGREEMENT * m for p, m, _ in pairs)
    ax.set_title(f"measured against predicted, per measured cell\n({inside} of {len(pairs)} inside the band, unnamed)",
                 fontsize=10)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    save(fig, path)


def main(argv=None) -> dict:
    return demo_main(NAME, argv)


if __name__ == "__main__":
    main()

"""The fleet's parameter drift, drawn: each actuator's estimates run by run."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..model.parameter_units import render
from ..util.numbers import significant
from ..workbench.drift import DRIFT_PARAMS
from .fits import plt, save

LABELS = {"RC_s": "time constant RC (s)", "betaR_K_per_effort2": "βR, rise per effort²",
          "T_offset_C": "offset T_offset (°C)"}


def _range(values: list[float]) -> tuple[float, float]:
    """The estimates' range, or their 5th to 95th percentiles when there are ten or more."""
    if not values:
        return 0.0, 1.0
    if len(values) >= 10:
        lo, hi = np.percentile(values, [5.0, 95.0])
        return float(lo), float(hi)
    return float(np.min(values)), float(np.max(values))


def plot_drift(records: list[dict], path: str | Path, effort_unit: str | None = None) -> Path:
    """Each actuator's estimates run by run (2-sigma bars), actuators side by side; flagged names in red.
    ``effort_unit``: the log's, for βR's axis (K per effort unit squared).

    The vertical range follows the estimates, not their bars, so that one
    unidentified run (huge bars) does not flatten the others; with ten or
    more estimates it spans their 5th to 95th percentiles, and an estimate
    beyond is drawn as a triangle on the edge with its value, so that one
    run with RC near 80,000 s does not flatten every other actuator.
    """
    fig, axes = plt.subplots(len(DRIFT_PARAMS), 1, figsize=(max(6.0, 1.1 * len(records) + 3.0),
                                                            2.5 * len(DRIFT_PARAMS)), sharex=True)
    n_runs = max((len(r["runs"]) for r in records), default=1)
    colors = plt.cm.viridis(np.linspace(0.0, 0.9, n_runs))
    for ax, p in zip(axes, DRIFT_PARAMS):
        shown, points = [], []
        for i, r in enumerate(records):
            q = r["params"].get(p)
            if not q:
                continue
            v, s = np.array(q["values"]), np.array(q["stderrs"])
            x = i + np.linspace(-0.3, 0.3, len(v)) if len(v) > 1 else np.array([float(i)])
            for k in range(len(v)):
                points.append((x[k], v[k], s[k], colors[k], i == 0 and f"run {k + 1}"))
            ax.hlines(q["mean"], i - 0.35, i + 0.35, color="red" if q["moved"] else "0.4", lw=1)
            shown += list(v)
        lo, hi = _range(shown)
        beyond = 0  # values written beside the edge's triangles, staggered so that neighbours' do not overlap
        for xk, vk, sk, color, label in points:
            if lo <= vk <= hi:
                ax.errorbar(xk, vk, yerr=2.0 * sk, fmt="o", color=color, ms=4, capsize=2, lw=1,
                            label=label or None)
            else:  # beyond the shown range: a triangle on the edge, with the value
                edge = hi if vk > hi else lo
                ax.plot(xk, edge, "^" if vk > hi else "v", color=color, ms=7, clip_on=False)
                step = 9 * (beyond % 2)
                beyond += 1
                ax.annotate(significant(vk, 4), (xk, edge), textcoords="offset points",
                            xytext=(4, -10 - step if vk > hi else 4 + step), fontsize=7)
        if shown:
            pad = 0.15 * (hi - lo) if hi > lo else 0.1 * abs(hi) + 1e-9
            ax.set_ylim(lo - pad, hi + pad)
        label = LABELS.get(p, p)
        if p == "betaR_K_per_effort2" and effort_unit:
            label = f"βR, rise per effort²\n({render('K/({effort})^2', {'effort': effort_unit})})"
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    fig.align_ylabels(axes)
    axes[-1].set_xticks(range(len(records)))
    axes[-1].set_xticklabels([r["actuator"] for r in records], rotation=45 if len(records) > 8 else 0)
    for label, r in zip(axes[-1].get_xticklabels(), records):
        label.set_color("red" if r["flagged"] else "black")
    flagged = sum(r["flagged"] for r in records)
    axes[0].set_title(f"Parameter drift across runs: {flagged} of {len(records)} actuator(s) flagged (red); "
                      f"bars 2 standard errors, line the weighted mean", fontsize=10)
    if n_runs <= 12:
        axes[0].legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    return save(fig, path)

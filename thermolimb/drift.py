"""Parameter drift across runs: does an actuator's identified RC, betaR or offset move beyond its uncertainty?

For each actuator and parameter, the runs' estimates ``v_i`` with standard
errors ``s_i`` are tested for one common value: the weighted mean
``m = sum(v_i / s_i^2) / sum(1 / s_i^2)`` and ``chi2 = sum(((v_i - m) / s_i)^2)``
on ``n - 1`` degrees of freedom.  An actuator is flagged when any parameter's
p-value is below ``alpha`` (default 0.001: with three parameters and a few
dozen actuators, about one false alarm in ten fleets of healthy actuators
when the standard errors are right) *and* it moves by more than
``min_change`` (default 5 %) of its mean, so that very precise estimates do
not flag changes nobody would act on.  A failing fan shows as a rising RC and
betaR (more thermal resistance); a dragging bearing as a rising offset or an
added loss.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

DRIFT_PARAMS = ("RC_s", "betaR_K_per_effort2", "T_offset_C")
ALPHA = 1e-3
MIN_CHANGE = 0.05


def drift(rows: list[dict], params: tuple[str, ...] = DRIFT_PARAMS, alpha: float = ALPHA,
          min_change: float = MIN_CHANGE) -> list[dict]:
    """One record per actuator with two or more fitted runs, in the rows' order."""
    from scipy.stats import chi2

    by_actuator: dict[str, list[dict]] = {}
    for row in rows:
        if not row.get("error") and row.get("params"):
            by_actuator.setdefault(row["actuator"], []).append(row)
    out = []
    for name, runs in by_actuator.items():
        if len(runs) < 2:
            continue
        record = {"actuator": name, "runs": [r["run"] for r in runs], "params": {}, "flagged": False, "why": []}
        for p in params:
            if not all(p in r["params"] for r in runs):
                continue
            v = np.array([r["params"][p]["value"] for r in runs])
            s = np.array([max(r["params"][p]["stderr"], 1e-12 * max(abs(x), 1e-300))
                          for r, x in zip(runs, v)])
            w = 1.0 / s**2
            mean = float(np.sum(w * v) / np.sum(w))
            stat = float(np.sum(((v - mean) / s) ** 2))
            p_value = float(chi2.sf(stat, len(v) - 1))
            change = float((v.max() - v.min()) / abs(mean)) if mean != 0 else float("inf")
            moved = p_value < alpha and change > min_change
            record["params"][p] = {"values": v.tolist(), "stderrs": s.tolist(), "mean": mean, "chi2": stat,
                                   "dof": len(v) - 1, "p_value": p_value, "change": change, "moved": moved}
            if moved:
                k = int(np.argmax(np.abs(v - mean) / s))
                record["flagged"] = True
                record["why"].append(f"{p} moves {100 * change:.0f} % across runs (chi2 = {stat:.1f} on {len(v) - 1} "
                                     f"dof, p = {p_value:.1e}); furthest from the mean in run {runs[k]['run']}")
        record["why"] = "; ".join(record["why"])
        out.append(record)
    return out


def format_drift(records: list[dict]) -> str:
    lines = [f"{'actuator':12s} {'runs':>4s}  " + "  ".join(f"{p:>24s}" for p in DRIFT_PARAMS) + "  drift"]
    for r in records:
        cells = []
        for p in DRIFT_PARAMS:
            q = r["params"].get(p)
            cells.append(f"{100 * q['change']:7.1f} % p={q['p_value']:<9.2g}" if q else f"{'':>24s}")
        lines.append(f"{r['actuator']:12s} {len(r['runs']):4d}  " + "  ".join(f"{c:>24s}" for c in cells)
                     + ("  FLAGGED: " + r["why"] if r["flagged"] else "  steady"))
    return "\n".join(lines)


def plot_drift(records: list[dict], path: str | Path) -> Path:
    """Each actuator's estimates run by run (2-sigma bars), actuators side by side; flagged names in red.

    The vertical range follows the estimates, not their bars, so that one
    unidentified run (huge bars) does not flatten the others.
    """
    from .plots import plt, save

    fig, axes = plt.subplots(len(DRIFT_PARAMS), 1, figsize=(max(6.0, 1.1 * len(records) + 3.0),
                                                            2.5 * len(DRIFT_PARAMS)), sharex=True)
    n_runs = max((len(r["runs"]) for r in records), default=1)
    colors = plt.cm.viridis(np.linspace(0.0, 0.9, n_runs))
    for ax, p in zip(axes, DRIFT_PARAMS):
        shown = []
        for i, r in enumerate(records):
            q = r["params"].get(p)
            if not q:
                continue
            v, s = np.array(q["values"]), np.array(q["stderrs"])
            x = i + np.linspace(-0.3, 0.3, len(v)) if len(v) > 1 else np.array([float(i)])
            for k in range(len(v)):
                ax.errorbar(x[k], v[k], yerr=2.0 * s[k], fmt="o", color=colors[k], ms=4, capsize=2, lw=1,
                            label=f"run {k + 1}" if i == 0 else None)
            ax.hlines(q["mean"], i - 0.35, i + 0.35, color="red" if q["moved"] else "0.4", lw=1)
            shown += list(v)
        if shown:
            lo, hi = float(np.min(shown)), float(np.max(shown))
            pad = 0.15 * (hi - lo) if hi > lo else 0.1 * abs(hi) + 1e-9
            ax.set_ylim(lo - pad, hi + pad)
        ax.set_ylabel(p)
        ax.grid(alpha=0.3)
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

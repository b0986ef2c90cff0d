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

import numpy as np

from ..identification.metrics import chi2_sf

DRIFT_PARAMS = ("RC_s", "betaR_K_per_effort2", "T_offset_C")
ALPHA = 1e-3
MIN_CHANGE = 0.05


def drift(rows: list[dict], params: tuple[str, ...] = DRIFT_PARAMS, alpha: float = ALPHA,
          min_change: float = MIN_CHANGE) -> list[dict]:
    """One record per actuator with two or more fitted runs, in the rows' order."""
    by_actuator: dict[str, list[dict]] = {}
    for row in rows:
        if not row.get("error") and row.get("params"):
            by_actuator.setdefault(row["actuator"], []).append(row)
    out = []
    for name, runs in by_actuator.items():
        if len(runs) < 2:
            continue
        record = {
            "actuator": name,
            "runs": [r["run"] for r in runs],
            "params": {},
            "flagged": False,
            "why": [],
        }
        for p in params:
            if not all(p in r["params"] for r in runs):
                continue
            v = np.array([r["params"][p]["value"] for r in runs])
            s = np.array([max(r["params"][p]["stderr"], 1e-12 * max(abs(x), 1e-300))
                          for r, x in zip(runs, v)])
            w = 1.0 / s**2
            mean = float(np.sum(w * v) / np.sum(w))
            stat = float(np.sum(((v - mean) / s) ** 2))
            p_value = chi2_sf(stat, len(v) - 1)
            change = float((v.max() - v.min()) / abs(mean)) if mean != 0 else float("inf")
            moved = p_value < alpha and change > min_change
            record["params"][p] = {"values": v.tolist(), "stderrs": s.tolist(), "mean": mean, "chi2": stat,
                                   "dof": len(v) - 1, "p_value": p_value, "change": change, "moved": moved}
            if moved:
                k = int(np.argmax(np.abs(v - mean) / s))
                record["flagged"] = True
                record["why"].append(f"{p} moves {100 * change:.0f} % across "
                                     f"runs (chi2 = {stat:.1f} on {len(v) - 1} "
                                     f"dof, p = {p_value:.1e}); furthest "
                                     f"from the mean in run {runs[k]['run']}")
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

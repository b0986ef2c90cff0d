"""The thermal audit's figure: every joint's temperature over the run, the limits, the limiting joint bold,
the six hottest named."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .fits import plt, save

LABELLED = 6


def plot_audit(result, path: Path) -> Path:
    """``result``: a :class:`~thermolimb.envs.audit.AuditResult`."""
    fig, ax = plt.subplots(figsize=(8, 4.5))
    limiting = result.limiting_joint()
    minutes = result.time_s / 60.0
    # the hottest are named, the rest grey
    named = set(np.argsort(-result.temperature_C.max(axis=0))[:LABELLED])
    for k, joint in enumerate(result.joints):
        bold = joint == limiting
        ax.plot(minutes, result.temperature_C[:, k], lw=2.2 if bold else 0.9, alpha=1.0 if bold else 0.7,
                label=joint if k in named else None, color=None if k in named else "0.7",
                zorder=3 if bold else 2)
    others = len(result.joints) - len(named)
    if others:  # the grey lines say what they are
        ax.plot([], [], color="0.7", lw=0.9, label=f"{others} other joint{'s' * (others > 1)}, lower peaks")
    for limit in np.unique(result.limit_C):
        ax.axhline(limit, ls="--", color="black", lw=0.8, label=f"limit {limit:.0f} degC")
    ax.set_xlabel("simulated time (min)")
    ax.set_ylabel("winding temperature (degC)")
    ax.set_title(f"{result.env_id}, policy {result.policy}: limiting joint {limiting}", fontsize=10)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, frameon=False)
    ax.grid(alpha=0.3)
    return save(fig, path)

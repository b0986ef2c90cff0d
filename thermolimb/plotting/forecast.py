"""The forecast's plot: the predicted temperature, its band, the threshold, and the log's readings."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .fits import plt, save


def plot_forecast(f, path: Path) -> Path:
    """One panel: the band at the forecast's level, the prediction, the threshold and where each crosses
    it."""
    fig, ax = plt.subplots(figsize=(8, 4.2))
    minutes = f.time_s / 60.0
    ax.fill_between(minutes, f.low_C, f.high_C, color="tab:blue", alpha=0.2,
                    label=f"{100 * f.level:.0f} % band")
    ax.plot(minutes, f.predicted_C, color="tab:blue", lw=1.5, label="predicted")
    if f.measured_C is not None:
        ax.plot(minutes, f.measured_C, color="black", lw=0.8, label="measured")
    ax.axhline(f.threshold_C, color="tab:red", ls="--", lw=1, label=f"threshold {f.threshold_C:.1f} degC")
    low, high = f.interval_s
    if f.time_to_threshold_s is not None:
        ax.axvline(f.time_to_threshold_s / 60.0, color="tab:blue", ls=":", lw=1)
    if low is not None:
        right = minutes[-1] if high is None else high / 60.0
        ax.axvspan(low / 60.0, right, color="tab:red", alpha=0.08, label="time to threshold, interval")
    ax.set_xlabel("time from the start (min)")
    ax.set_ylabel("temperature (degC)")
    ax.set_title(f.sentence(), fontsize=9, wrap=True)
    top = max(float(np.max(f.high_C)), f.threshold_C)
    ax.set_ylim(top=top + 0.05 * (top - float(np.min(f.low_C)) + 1e-9))
    # beside the data, never on it
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    ax.grid(alpha=0.3)
    return save(fig, path)

"""The monitor's plot: its winding estimate against the true winding (when known) and the thermistor."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .fits import plt, save


def plot_monitor(
    time_s, true_winding_C, measured_C, estimate_time_s, estimate_C, estimate_std_K, path: Path
) -> Path:
    fig, ax = plt.subplots(figsize=(8, 4.2))
    minutes = np.asarray(estimate_time_s) / 60.0
    ax.fill_between(minutes, estimate_C - 2 * estimate_std_K, estimate_C + 2 * estimate_std_K,
                    color="tab:blue", alpha=0.2, label="estimate ± 2 sd")
    ax.plot(minutes, estimate_C, color="tab:blue", lw=1.2, label="monitor's winding estimate")
    if true_winding_C is not None:
        ax.plot(np.asarray(time_s) / 60.0, true_winding_C, color="tab:red", lw=0.8, label="true winding "
                "(plant)")
    ax.plot(np.asarray(time_s) / 60.0, measured_C, color="black", lw=0.6, alpha=0.7, label="thermistor")
    ax.set_xlabel("time (min)")
    ax.set_ylabel("temperature (degC)")
    ax.set_title("thermolimb monitor on a walking run", fontsize=10)
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(alpha=0.3)
    return save(fig, path)

"""Plots written by the command line and the demos (Matplotlib, no screen needed)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .evaluation import FitReport  # noqa: E402


def save(fig, path: Path) -> Path:
    """Write a figure whole (to a temporary name first) and close it."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.stem + ".partial.png")
    fig.savefig(tmp, dpi=110, bbox_inches="tight")
    plt.close(fig)
    tmp.replace(path)
    return path


def plot_fit(report: FitReport, path: Path) -> Path:
    """Measured and simulated temperature over training and validation, their error, and effort."""
    fig, axes = plt.subplots(3, 1, figsize=(10, 8), sharex=True, height_ratios=[3, 1.4, 1.4])
    for i, seg in enumerate(report.train_segments):
        axes[0].plot(seg.time_s, seg.measured_C, color="0.3", lw=1, label="measured" if i == 0 else None)
        axes[0].plot(seg.time_s, seg.simulated_C, color="tab:blue", lw=1.2,
                     label="model, training (free run)" if i == 0 else None)
        axes[1].plot(seg.time_s, seg.simulated_C - seg.measured_C, color="tab:blue", lw=0.8)
        axes[2].plot(seg.time_s, seg.effort, color="0.4", lw=0.6)
    for i, seg in enumerate(report.validation_segments):
        axes[0].plot(seg.time_s, seg.measured_C, color="0.3", lw=1)
        axes[0].plot(seg.time_s, seg.simulated_C, color="tab:orange", lw=1.2,
                     label="model, validation (free run from the split)" if i == 0 else None)
        axes[0].axvline(seg.time_s[0], color="k", ls=":", lw=0.8)
        axes[1].plot(seg.time_s, seg.simulated_C - seg.measured_C, color="tab:orange", lw=0.8)
        axes[2].plot(seg.time_s, seg.effort, color="0.4", lw=0.6)
    v = report.validation
    axes[0].set_title(
        f"{report.actuator}: model {','.join(report.model.terms)} ({report.method}); validation "
        f"RMSE {v['rmse_K']:.2f} K, max {v['max_abs_K']:.2f} K, fit {v['fit_percent']:.1f} %"
    )
    axes[0].set_ylabel("temperature (°C)")
    axes[0].legend(loc="best", fontsize=8)
    axes[1].axhline(0, color="k", lw=0.5)
    axes[1].set_ylabel("error (K)")
    axes[2].set_ylabel("effort (N m)")
    axes[2].set_xlabel("time (s)")
    return save(fig, path)

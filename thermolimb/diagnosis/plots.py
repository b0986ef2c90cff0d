"""Diagnosis plots: residual over time, its autocorrelation, cross-correlations, candidates, waterfall."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..plots import plt, save
from .diagnose import Diagnosis


def plot_residuals(d: Diagnosis, path: Path) -> Path:
    a = d.residuals
    n_cross = len(a.cross)
    fig, axes = plt.subplots(2 + (n_cross + 1) // 2, 2, figsize=(11, 3 + 2.2 * ((n_cross + 1) // 2 + 1)))
    ax = plt.subplot2grid(axes.shape, (0, 0), colspan=2, fig=fig)
    for extra in axes[0]:
        extra.remove()
    ax.plot(a.time_s, a.residual_K, lw=0.7)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_title(f"{d.actuator}: residual of {','.join(d.model)} on the training part (measured − simulated)")
    ax.set_ylabel("residual (K)")
    ax.set_xlabel("time (s)")
    ac = axes[1, 0]
    ac.plot(a.autocorrelation.lags_s, a.autocorrelation.values)
    ac.axhspan(-a.autocorrelation.band, a.autocorrelation.band, color="0.85")
    ac.set_title("autocorrelation (band: white residual)")
    ac.set_xlabel("lag (s)")
    ph = axes[1, 1]
    names = list(a.phase_rmse_K)
    ph.barh(names, [a.phase_rmse_K[n] for n in names], color="tab:gray")
    ph.set_title("where the fit is worst: RMSE by phase (K)")
    for i, (name, c) in enumerate(a.cross.items()):
        axc = axes[2 + i // 2, i % 2]
        axc.plot(c.lags_s, c.values, color="tab:red" if c.significant else "tab:blue")
        axc.axhspan(-c.band, c.band, color="0.85")
        axc.set_title(f"cross-correlation with {name} (band: Bartlett)", fontsize=9)
        axc.set_xlabel("lag (s)")
    for j in range(n_cross, 2 * ((n_cross + 1) // 2)):
        axes[2 + j // 2, j % 2].axis("off")
    fig.tight_layout()
    return save(fig, path)


def plot_candidates(d: Diagnosis, path: Path) -> Path:
    refitted = [c for c in d.candidates if c.rmse_K is not None]
    fig, ax = plt.subplots(figsize=(8, 0.5 * len(refitted) + 1.8))
    labels = [c.effect + (f" (for {c.replaces})" if c.replaces else "") for c in refitted]
    ax.barh(labels[::-1], [c.rmse_K for c in refitted][::-1],
            color=["tab:green" if c is d.recommended else "tab:blue" for c in refitted][::-1])
    ax.axvline(d.base.validation["rmse_K"], color="k", ls="--", label="current model")
    ax.set_xlabel("validation RMSE (K)")
    ax.set_title(f"{d.actuator}: candidate effects refitted; recommended: "
                 f"{d.recommended.effect if d.recommended else 'none'}")
    ax.legend(fontsize=8)
    return save(fig, path)


def _step_label(prev: dict, step: dict) -> str:
    added = sorted(set(step["model"]) - set(prev["model"]))
    removed = sorted(set(prev["model"]) - set(step["model"]))
    return "+ " + ",".join(added) + (f" (for {','.join(removed)})" if removed else "")


def plot_waterfall(steps: list[dict], actuator: str, path: Path) -> Path:
    fig, ax = plt.subplots(figsize=(8, 3.5))
    rmse = [s["rmse_K"] for s in steps]
    labels = ["base: " + ",".join(steps[0]["model"])] + [_step_label(prev, s) for prev, s in zip(steps, steps[1:])]
    ax.bar(np.arange(len(rmse)), rmse, color="tab:blue")
    for i, v in enumerate(rmse):
        ax.text(i, v, f"{v:.3f} K", ha="center", va="bottom", fontsize=8)
    ax.set_xticks(np.arange(len(rmse)), labels, rotation=15, fontsize=8)
    ax.set_ylabel("validation RMSE (K)")
    ax.set_title(f"{actuator}: validation error as effects are added")
    return save(fig, path)


def plot_diagnosis(d: Diagnosis, folder: Path, stem: str) -> list[Path]:
    """Every diagnosis plot of one actuator into ``folder``: residuals, candidates, and the waterfall if any."""
    folder = Path(folder)
    paths = [plot_residuals(d, folder / f"residuals_{stem}.png"), plot_candidates(d, folder / f"candidates_{stem}.png")]
    if d.auto:
        paths.append(plot_waterfall(d.auto, d.actuator, folder / f"waterfall_{stem}.png"))
    return paths

"""Diagnosis plots: where the model fails (overlay, residual, correlations), the changes tried, the walk."""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np

from ..model.terms import readable
from ..util.numbers import places3
from ..workbench.diagnosis.diagnose import Diagnosis
from .fits import overlay, plot_comparison, plt, save

STATUS_COLOURS = {"helps": "tab:green", "unstable": "tab:orange", "does not help": "tab:blue",
                  "implausible": "tab:red", "unidentifiable": "tab:purple", "refit failed": "0.5"}


def plot_residuals(d: Diagnosis, path: Path) -> Path:
    """Measured against the model's free run, the residual beneath, then its autocorrelation, phases and
    correlations."""
    a = d.residuals
    n_cross = len(a.cross)
    rows = 3 + (n_cross + 1) // 2
    fig = plt.figure(figsize=(11, 3.2 + 2.2 * rows))
    grid = fig.add_gridspec(rows, 2, height_ratios=[2.2, 1.2] + [1.0] * (rows - 2))
    top = fig.add_subplot(grid[0, :])
    err = fig.add_subplot(grid[1, :], sharex=top)
    overlay(d.base, top, err)
    v = d.base.validation
    top.set_title(f"{d.actuator}: measured temperature and the free "
                  f"run of the model, {readable(','.join(d.model))}\n"
                  + textwrap.fill(f"validation (shaded) RMSE {v['rmse_K']:.3f} "
                                  f"K, largest error {v['max_abs_K']:.3f} K; "
                                  f"{d.base.scheme}", 140), fontsize=10)
    err.set_title("residual: where the model fails", fontsize=9)
    err.set_xlabel("time (s; runs one after another)")
    ac = fig.add_subplot(grid[2, 0])
    ac.plot(a.autocorrelation.lags_s, a.autocorrelation.values)
    ac.axhspan(-a.autocorrelation.band, a.autocorrelation.band, color="0.85")
    ac.set_title("autocorrelation of the training residual (grey: white noise)", fontsize=9)
    ac.set_xlabel("lag (s)")
    ph = fig.add_subplot(grid[2, 1])
    names = list(a.phase_rmse_K)
    ph.barh(names, [a.phase_rmse_K[n] for n in names], color="tab:gray")
    ph.set_title("where the fit is worst: training RMSE by phase (K)", fontsize=9)
    for i, (name, c) in enumerate(a.cross.items()):
        axc = fig.add_subplot(grid[3 + i // 2, i % 2])
        axc.axhspan(-c.band, c.band, color="0.85")
        axc.plot(c.lags_s, c.values, color="tab:blue", lw=0.8)
        outside = np.abs(np.asarray(c.values)) > c.band
        axc.plot(np.asarray(c.lags_s)[outside], np.asarray(c.values)[outside], ".", color="tab:red", ms=2)
        axc.set_title(f"residual vs {name}: cross-correlation\n(red: lags outside Bartlett's band)",
                      fontsize=9)
        axc.set_xlabel("lag (s)")
    fig.tight_layout()
    return save(fig, path)


def plot_candidates(d: Diagnosis, path: Path) -> Path:
    """Held-out gain of every refitted change, coloured by its status; the others listed with why."""
    return save(candidates_figure(d), path)


def candidates_figure(d: Diagnosis):
    """The figure :func:`plot_candidates` writes: a failed refit's bar carries its reason, as the table
    does."""
    refitted = [c for c in d.candidates if c.refitted]
    others = [c for c in d.candidates if not c.refitted]
    # each change in words with its identifier, wrapped so that the axes keep their width
    labels = [textwrap.fill(readable(c.label), 30) for c in refitted][::-1]
    # a row as tall as the longest label's lines need (a channel's form runs to five), so that labels do not
    # overlap
    row_in = max([0.45] + [0.17 * (label.count("\n") + 1) for label in labels])
    fig, ax = plt.subplots(figsize=(9, row_in * max(len(refitted), 1) + 1.6 + 0.18 * len(others)))
    gains = [100 * c.improvement for c in refitted][::-1]
    colours = [STATUS_COLOURS.get(c.status, "tab:blue") for c in refitted][::-1]
    ax.barh(labels, gains, color=colours)
    for y, c in enumerate(refitted[::-1]):
        mark = "  ← recommended" if c is d.recommended else ""
        why = f": {c.failure}" if c.failure else ""
        taken = (", taken "
                 f"{round(c.selection_frequency * d.stability['replicates'])}/{d.stability['replicates']}"
                 if c.selection_frequency is not None else "")
        ax.text(max(100 * c.improvement, 0), y, f"  {c.status}, {c.rmse_K:.3f} K{taken}{mark}{why}",
                va="center", fontsize=8)
    ax.axvline(0, color="k", lw=0.8)
    ax.axvline(10, color="tab:green", ls=":", lw=0.8, label="10 % needed to add an effect")
    lo, hi = ax.get_xlim()
    ax.set_xlim(lo, hi + 0.6 * (hi - lo))  # room for the labels right of the bars
    ax.set_xlabel(f"held-out gain: fall of validation RMSE from {d.base.validation['rmse_K']:.3f} K (%)")
    thin = ("" if d.base.evidence.rankable else " (evidence too thin)") or (
        " (at the sensor's floor)" if d.at_floor else ""
    )
    ax.set_title(
        textwrap.fill(
            f"{d.actuator}: changes to the model, "
            f"{readable(','.join(d.model))}, tried; recommended: "
            f"{readable(d.recommended.label) if d.recommended else 'none'}{thin}",
            95,
        ),
        fontsize=10,
    )
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in STATUS_COLOURS.values()]
    ax.legend(handles + ax.get_legend_handles_labels()[0],
              list(STATUS_COLOURS) + ["10 % needed to add an effect"], fontsize=7, loc="upper left",
              bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    if others:
        text = "\n".join(f"{readable(c.label)}: {c.status} "
                         f"({c.confounded.split(':')[0] if c.confounded else c.not_refitted_because})"
                         for c in others)
        fig.text(0.01, 0.0, "not refitted:\n" + text, fontsize=7, va="top")
    return fig


def waterfall_bars(steps: list[dict]) -> tuple[list[str], list[float], list[str]]:
    """The waterfall's bars: each step taken (with how often its replicates took it), then, where the walk
    stopped at a change that helps but is held back (unstable, or refuted by the run's other part), that
    change (``kind`` "unstable")."""
    def taken(s):
        f = s.get("selection_frequency")
        return "" if f is None else f" (taken {round(100 * f)} %)"

    labels = [readable("start: " + ",".join(steps[0]["model"]))] + [readable(s.get("change", "")) + taken(s)
                                                                     for s in steps[1:]]
    rmse = [s["rmse_K"] for s in steps]
    kinds = ["flagged" if s["flags"] else "taken" for s in steps]
    tail = steps[-1].get("unstable")
    if tail and tail.get("status") == "refuted":
        labels.append(f"{readable(tail['change'])} (refuted by the run's other part: not taken)")
    elif tail:
        labels.append(f"{readable(tail['change'])} (taken "
                      f"{round(tail['selection_frequency'] * tail['replicates'])} of "
                      f"{tail['replicates']}: not taken)")
    if tail:
        rmse.append(tail["rmse_K"])
        kinds.append("unstable")
    return labels, rmse, kinds


def plot_waterfall(steps: list[dict], actuator: str, path: Path) -> Path:
    fig, ax = plt.subplots(figsize=(8, 3.8))
    labels, rmse, kinds = waterfall_bars(steps)
    # long names (a discovered form's) wrapped at underscores and spaces, so that neighbouring labels do not
    # overlap
    labels = [textwrap.fill(label.replace("_", "_ "), 20).replace("_ ", "_") for label in labels]
    colours = {"taken": "tab:blue", "flagged": "tab:red", "unstable": "white"}
    ax.bar(np.arange(len(rmse)), rmse, color=[colours[k] for k in kinds],
           edgecolor=["tab:orange" if k == "unstable" else "none" for k in kinds],
           linewidth=1.2)
    for i, v in enumerate(rmse):
        ax.text(i, v, f"{v:.3f} K", ha="center", va="bottom", fontsize=8)
    floor = steps[-1].get("floor_K")
    if floor:
        ax.axhline(floor, color="0.4", ls="--", lw=0.8, label=f"sensor's floor, {places3(floor)} K")
        ax.legend(fontsize=7, loc="upper right")
    ax.set_xticks(np.arange(len(rmse)), labels, rotation=0, fontsize=7)
    ax.set_ylabel("validation RMSE (K)")
    held = "orange outline: helps, but held back (unstable or refuted), not taken"
    notes = ["red: fitted values flagged"] + ([held] if "unstable" in kinds else [])
    ax.set_title(f"{actuator}: validation error at each step of the search\n({'; '.join(notes)})", fontsize=9)
    return save(fig, path)


def plot_diagnosis(d: Diagnosis, folder: Path, stem: str, steps=()) -> list[Path]:
    """Every diagnosis plot of one actuator into ``folder``: residuals, candidates, and, after a search
    (``steps``: its diagnoses), the waterfall and every step's model over the measurement with its
    residual."""
    folder = Path(folder)
    paths = [
        plot_residuals(d, folder / f"residuals_{stem}.png"),
        plot_candidates(d, folder / f"candidates_{stem}.png"),
    ]
    if d.auto:
        paths.append(plot_waterfall(d.auto, d.actuator, folder / f"waterfall_{stem}.png"))
    if len(steps) > 1:
        paths.append(
            plot_comparison([(s.base, None) for s in steps], d.actuator, folder / f"steps_{stem}.png")
        )
    return paths

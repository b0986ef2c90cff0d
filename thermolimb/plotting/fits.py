"""Plots written by the command line and the demos (Matplotlib, no screen needed)."""

from __future__ import annotations

import textwrap
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.text import Text  # noqa: E402

from ..model.parameter_units import NOT_GIVEN  # noqa: E402
from ..model.terms import readable  # noqa: E402
from ..util.atomic import atomic_path  # noqa: E402
from ..util.errors import bounded  # noqa: E402
from ..workbench.validation import FitReport  # noqa: E402
from .inventory import metadata  # noqa: E402

LABEL_WORD_LIMIT = 100  # characters of one word a figure's text shows
DPI = 110
# the report's column (1320 px less its padding): a wider figure is drawn at a lower resolution
WIDEST_PX = 1280


def save(fig, path: Path) -> Path:
    """Write a figure whole (to a temporary name first) and close it; a PNG carries what it draws
    (inventory)."""
    path = Path(path)
    kind = path.suffix.lstrip(".").lower() or "png"
    # a name of any length (an actuator's) keeps the figure drawable and readable
    for text in fig.findobj(Text):
        if len(text.get_text()) > LABEL_WORD_LIMIT:
            text.set_text(bounded(text.get_text(), LABEL_WORD_LIMIT))
    wrap_to_figure(fig)
    width_in = fig.get_tightbbox(fig.canvas.get_renderer()).width + 0.2  # savefig's pad_inches on each side
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, dpi=min(DPI, WIDEST_PX / width_in), bbox_inches="tight", format=kind,
                        metadata=metadata(fig) if kind == "png" else None)
    finally:
        plt.close(fig)
    return path


def wrap_to_figure(fig) -> None:
    """Wrap every text that runs past the figure's right edge (a long note, a failed refit's reason) to the
    room it has, so that a figure stays as wide as it was drawn and a page's column shows it legibly.  Texts
    that start beyond the edge (a legend placed outside the axes) are left alone."""
    renderer = fig.canvas.get_renderer()
    right = fig.bbox.x1
    for text in fig.findobj(Text):
        content = text.get_text()
        if not content or "$" in content or not text.get_visible() or text.get_rotation() != 0:
            continue
        box = text.get_window_extent(renderer)
        room = right - box.x0
        if box.x1 <= right + 1 or room < 0.2 * fig.bbox.width or box.width <= 0:
            continue
        longest = max(len(line) for line in content.split("\n"))
        width = max(24, int(longest * room / box.width * 0.95))
        text.set_text("\n".join(textwrap.fill(line, width, subsequent_indent="  ", break_on_hyphens=False)
                                for line in content.split("\n")))


def run_offsets(segments) -> dict[str, float]:
    """Time shift per run, so that runs are drawn one after another with a small gap: runs that each start at
    0 s apart, and hours between two parts of a day's log closed."""
    offsets, end = {}, None
    for seg in segments:
        if seg.run in offsets:
            continue
        start = float(seg.time_s[0])
        offsets[seg.run] = 0.0 if end is None else end + 0.02 * max(end, 1.0) - start
        end = max(float(s.time_s[-1]) for s in segments if s.run == seg.run) + offsets[seg.run]
    return offsets


def overlay(report: FitReport, ax_temperature, ax_error=None, ax_effort=None) -> None:
    """Measured temperature and the model's free run, validation shaded; the error and effort beneath if
    given."""
    segments = list(report.train_segments) + list(report.validation_segments)
    shift = run_offsets(sorted(segments, key=lambda s: (s.run, float(s.time_s[0]))))
    for part, color, segs in (("training", "tab:blue", report.train_segments),
                              ("validation", "tab:orange", report.validation_segments)):
        for i, seg in enumerate(segs):
            t = seg.time_s + shift[seg.run]
            ax_temperature.plot(t, seg.measured_C, color="0.2", lw=1,
                                label="measured" if part == "training" and i == 0 else None)
            ax_temperature.plot(t, seg.simulated_C, color=color, lw=1.2,
                                label=f"model free run, {part}" if i == 0 else None)
            if part == "validation":
                for ax in (ax_temperature, ax_error, ax_effort):
                    if ax is not None:
                        ax.axvspan(t[0], t[-1], color="tab:orange", alpha=0.08, lw=0)
            if ax_error is not None:
                ax_error.plot(t, seg.measured_C - seg.simulated_C, color=color, lw=0.8)
            if ax_effort is not None:
                ax_effort.plot(t, seg.effort, color="0.4", lw=0.6)
    ax_temperature.set_ylabel("temperature (°C)")
    # off the data
    ax_temperature.legend(loc="upper left", bbox_to_anchor=(1.005, 1.0), fontsize=8, frameon=False)
    if ax_error is not None:
        ax_error.axhline(0, color="k", lw=0.5)
        ax_error.set_ylabel("measured − model (K)")
    if report.flags:  # under the figure, off the data (the saved figure grows to hold them)
        import textwrap

        lines = [textwrap.fill("! " + f, 160) for f in report.flags]
        ax_temperature.figure.text(0.01, 0.0, "\n".join(lines), fontsize=7, color="tab:red", va="top")


def effort_unit(report: FitReport) -> str:
    """The effort's unit as the log gives it, for an axis label (``N m``, ``mA``, or ``unit not given``)."""
    return report.channel_units.get("effort", NOT_GIVEN)


def plot_fit(report: FitReport, path: Path) -> Path:
    """Measured and simulated temperature over training and validation (shaded), their error, and effort."""
    fig, axes = plt.subplots(3, 1, figsize=(10, 8), sharex=True, height_ratios=[3, 1.4, 1.4])
    overlay(report, axes[0], axes[1], axes[2])
    v = report.validation
    axes[0].set_title(
        f"{report.actuator}: model {','.join(report.model.terms)} ({report.method}); validation (shaded) "
        f"RMSE {v['rmse_K']:.2f} K, largest error {v['max_abs_K']:.2f} K\n{report.scheme}",
        fontsize=10)
    axes[2].set_ylabel(f"effort ({effort_unit(report)})")
    axes[2].set_xlabel("time (s; runs one after another)")
    return save(fig, path)


def plot_comparison(results, actuator: str, path: Path) -> Path:
    """Measured temperature and each model's free run on held-out data, residuals below (``results``: reports
    with their information criteria, as :func:`~thermolimb.workbench.compare.compare_models` returns them)."""
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(10, 6), sharex=True, height_ratios=[2, 1])
    first = results[0][0]
    for seg in first.validation_segments:
        top.plot(seg.time_s, seg.measured_C, color="k", lw=1)
    for k, (report, _) in enumerate(results):
        # one colour per model, on every run
        label, colour = readable(",".join(report.model.terms)), f"C{k % 10}"
        for i, seg in enumerate(report.validation_segments):
            top.plot(seg.time_s, seg.simulated_C, lw=1, color=colour, label=label if i == 0 else None)
            bottom.plot(seg.time_s, seg.measured_C - seg.simulated_C, lw=0.8, color=colour)
    top.set_title(f"{actuator}: measured (black) and each model's free run on held-out data")
    top.set_ylabel("temperature (°C)")
    top.legend(fontsize=8)
    bottom.axhline(0, color="k", lw=0.5)
    bottom.set_ylabel("measured − model (K)")
    bottom.set_xlabel("time (s)")
    return save(fig, path)

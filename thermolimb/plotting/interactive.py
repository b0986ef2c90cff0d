"""Interactive figures in one self-contained HTML page (Plotly), for zooming into where a model drifts.

Plotly's JavaScript is embedded once per page and nothing is loaded from the
internet, so a page opens offline and can be mailed as one file.  Time-series
panels of one figure share their time axis: zooming one zooms all.  Series
longer than ``MAX_POINTS`` samples are thinned to every k-th sample (said
in the figure's caption); static PNGs stay the format for papers.
"""

from __future__ import annotations

import html
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..model.terms import readable
from ..util.atomic import write_text
from ..util.numbers import places3
from .diagnosis import STATUS_COLOURS
from .fits import run_offsets

MAX_POINTS = 50_000
COLORS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#17becf")


def _thin(n: int) -> int:
    return max(1, int(np.ceil(n / MAX_POINTS)))


@dataclass
class InteractivePage:
    """Figures with headings and captions, written as one HTML page."""

    title: str
    intro: str = ""
    sections: list = field(default_factory=list)

    def add(self, heading: str, figure, caption: str = "") -> None:
        self.sections.append((heading, figure, caption))

    def to_html(self) -> str:
        parts = ["<!doctype html><html><head><meta charset='utf-8'>",
                 f"<title>{html.escape(self.title)}</title>",
                 "<style>body{font-family:sans-serif;max-width:1200px;margin:auto;padding:1em}"
                 ".caption{color:#444;font-size:14px;margin:0 0 2em}</style></head><body>",
                 f"<h1>{html.escape(self.title)}</h1>"]
        if self.intro:
            parts.append(f"<p>{html.escape(self.intro)}</p>")
        for k, (heading, figure, caption) in enumerate(self.sections):
            parts.append(f"<h2>{html.escape(heading)}</h2>")
            parts.append(figure.to_html(full_html=False, include_plotlyjs=(k == 0), div_id=f"figure-{k}",
                                        config={"displaylogo": False}))
            if caption:
                parts.append(f"<p class='caption'>{html.escape(caption)}</p>")
        parts.append("</body></html>")
        return "\n".join(parts)

    def write(self, path: str | Path) -> Path:
        if not self.sections:
            self.intro = (
                self.intro + " " if self.intro else ""
            ) + "Nothing was computed, so there is no figure."
        return write_text(path, self.to_html())


def _segments(report, which: str):
    return report.validation_segments if which == "validation" else report.train_segments


def temperature_figure(reports: list, actuator: str):
    """Measured against each model's free run (training and validation), the residual, and the effort.

    ``reports``: ``[(label, FitReport)]``; the first one's measured temperature is drawn.
    """
    from plotly.subplots import make_subplots

    fig = make_subplots(rows=3, cols=1, shared_xaxes=True, vertical_spacing=0.04,
                        row_heights=[0.55, 0.25, 0.2])
    first = reports[0][1]
    segments = sorted(list(first.train_segments) + list(first.validation_segments),
                      key=lambda s: (s.run, float(s.time_s[0])))
    shift = run_offsets(segments)  # runs one after another, as the PNG draws them
    for k, seg in enumerate(segments):
        step = _thin(len(seg.time_s))
        t = seg.time_s + shift[seg.run]
        fig.add_scatter(x=t[::step], y=seg.measured_C[::step], row=1, col=1, name="measured",
                        line={"color": "black", "width": 1}, legendgroup="measured", showlegend=k == 0)
        fig.add_scatter(x=t[::step], y=seg.effort[::step], row=3, col=1, name="effort",
                        line={"color": "gray", "width": 0.8}, legendgroup="effort", showlegend=k == 0)
    for i, (label, report) in enumerate(reports):
        color = COLORS[i % len(COLORS)]
        for part, dash in (("train", "dot"), ("validation", "solid")):
            for k, seg in enumerate(_segments(report, part)):
                step = _thin(len(seg.time_s))
                name = f"{label} ({part})"
                t = seg.time_s + shift.get(seg.run, 0.0)
                fig.add_scatter(x=t[::step], y=seg.simulated_C[::step], row=1, col=1, name=name,
                                legendgroup=name, showlegend=k == 0,
                                line={"color": color, "width": 1.4, "dash": dash})
                fig.add_scatter(x=t[::step], y=(seg.measured_C - seg.simulated_C)[::step], row=2, col=1,
                                name=f"{name} residual", legendgroup=name, showlegend=False,
                                line={"color": color, "width": 1, "dash": dash})
    for seg in first.validation_segments:
        fig.add_vrect(x0=float(seg.time_s[0]) + shift[seg.run], x1=float(seg.time_s[-1]) + shift[seg.run],
                      fillcolor="orange", opacity=0.08, line_width=0)
    fig.update_yaxes(title_text="temperature (°C)", row=1, col=1)
    fig.update_yaxes(title_text="measured − model (K)", row=2, col=1)
    fig.update_yaxes(title_text=f"effort ({first.channel_units.get('effort', 'unit not given')})", row=3,
                     col=1)
    fig.update_xaxes(title_text="time (s; runs one after another)", row=3, col=1)
    fig.update_layout(height=720, title=f"{actuator}: measured and model temperature (validation shaded)",
                      hovermode="x unified", margin={"t": 60, "l": 70, "r": 20, "b": 50})
    return fig


def _hex(colour: str) -> str:
    """A Matplotlib colour as the PNGs draw it, for Plotly (the same step in the same colour on both)."""
    from matplotlib.colors import to_hex

    return to_hex(colour)


def candidates_figure(d):
    """Held-out gain (%) of every refitted change to the model, the recommended one marked."""
    import plotly.graph_objects as go

    refitted = [c for c in d.candidates if c.refitted]
    labels = [readable(c.label) + ("  ← recommended" if c is d.recommended else "") for c in refitted]
    fig = go.Figure(go.Bar(x=[100 * c.improvement for c in refitted], y=labels, orientation="h",
                           text=[f"{c.status}, {c.rmse_K:.3f} K" for c in refitted], textposition="outside",
                           marker_color=[_hex(STATUS_COLOURS.get(c.status, "tab:blue")) for c in refitted]))
    fig.add_vline(x=10.0, line_dash="dot", line_color="green", annotation_text="10 % needed")
    gains = [100 * c.improvement for c in refitted] or [0.0]
    low, high = min(min(gains), 0.0), max(max(gains), 10.0)
    # room for the labels
    fig.update_xaxes(range=[low - 0.1 * (high - low) - 5.0, high + 0.45 * (high - low)])
    fig.update_layout(height=160 + 40 * len(refitted), title=f"{d.actuator}: changes tried on held-out data",
                      xaxis_title=f"fall of validation RMSE from {d.base.validation['rmse_K']:.3f} K (%)",
                      yaxis={"autorange": "reversed"}, margin={"l": 260, "r": 40, "t": 60, "b": 50})
    return fig


def waterfall_figure(steps: list[dict], actuator: str):
    """Validation RMSE at each step of the stepwise search."""
    import plotly.graph_objects as go

    from .diagnosis import waterfall_bars

    labels, rmse, kinds = waterfall_bars(steps)  # named as the PNG names them
    # matplotlib's tab:blue, tab:red
    colours = {"taken": "#1f77b4", "flagged": "#d62728", "unstable": "white"}
    fig = go.Figure(go.Bar(x=labels, y=rmse, text=[f"{v:.3f} K" for v in rmse], textposition="outside",
                           marker={"color": [colours[k] for k in kinds],
                                   "line": {"color": ["#ff7f0e" if k == "unstable" else "rgba(0,0,0,0)"
                                                      for k in kinds], "width": 2}}))
    floor = steps[-1].get("floor_K")
    if floor:
        fig.add_hline(y=floor, line_dash="dash", line_color="gray",
                      annotation_text=f"sensor's floor, {places3(floor)} K")
    fig.update_layout(height=380, title=f"{actuator}: validation RMSE at each step of the search",
                      yaxis_title="validation RMSE (K)", margin={"t": 60, "b": 80})
    return fig


def thinning_note(report) -> str:
    n = max((len(s.time_s) for s in list(report.train_segments) + list(report.validation_segments)),
            default=0)
    step = _thin(n)
    return f" Drawn at every {step}-th sample (runs of up to {n} samples)." if step > 1 else ""


def add_diagnosis(page: InteractivePage, d, steps=()) -> None:
    """The model against the measurement, the candidates, and the waterfall when the search ran.

    ``steps``: every step of a stepwise search (diagnoses, the first being ``d``), each step's model drawn
    over the measurement with its residual, so that the error is seen to fall.
    """
    reports = [(",".join(s.model), s.base) for s in (steps or [d])]
    page.add(f"{d.actuator}: measured against the model", temperature_figure(reports, d.actuator),
             "Measured temperature (black) and each model's free "
             "run from each run's first reading; dotted where it "
             "was fitted, solid on held-out data (shaded). Zoom on any panel: the three share the time axis."
             + thinning_note(d.base))
    page.add(f"{d.actuator}: what the diagnosis tried", candidates_figure(d),
             "Each refitted change to the model and how much it "
             "lowers the held-out error; an effect is recommended "
             "when it gains at least 10 % and is plausible and "
             "identifiable, the model is not yet at the sensor's "
             "floor, and the search takes it in enough of the perturbed replicates (taken k/K).")
    if d.auto:
        page.add(f"{d.actuator}: the search, step by step", waterfall_figure(d.auto, d.actuator),
                 "Validation RMSE after each change the search took.")

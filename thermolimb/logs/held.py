"""A temperature held between its updates, read on the updates.

A logger that merges a slow temperature topic (1 Hz) into the rows of a fast one (joint states at 20 Hz or
more) and fills the blanks -- PlotJuggler's CSV export, a pandas ``ffill``, a driver that republishes its last
reading at the control rate -- repeats each reading until the next.  Read row by row, the held value is half an
update period old on average, and a model reads that delay as physics: the 1 Hz temperatures of a plant with no
lagging sensor, filled onto 20 Hz rows and read row by row, walk to ``+ sensor_lag``; read on their updates, the
walk takes no lag (and reads twenty times fewer samples).

**What counts as held.**  A column that changes only on a clock: at least :data:`MIN_CHANGES` changes, an
update period at least :data:`MIN_ROWS` rows long, and at least :data:`SHARE` of its changes within a row
interval (and a hundredth of the period) of one grid of that period laid over the whole log.  An update that
repeats the reading before it is invisible in the values, so the gaps between changes may be any whole number
of periods; it is the grid, one phase over the whole log, that a sensor sampled row by row does not follow: a
quantised temperature changes when it crosses a step, at instants that follow its slope, and a steady ramp's
regular steps drift off any one grid as soon as the slope changes.  A temperature updated irregularly is not
recognised (said in docs/logs.md).

**How it is read.**  The log's samples become the grid's instants within it (each taking the value the column
shows just after the instant, so an update a row late counts); the inputs are averaged over each interval by
:mod:`.align`'s rule, as for a temperature logged on its own time column.
"""

from __future__ import annotations

import numpy as np

from ..util.lazy import pandas as pd
from .align import ROOT_MEAN_SQUARE, interval_average

MIN_CHANGES = 20
MIN_ROWS = 4
SHARE = 0.9


def update_grid(time_s: np.ndarray, temperature_C: np.ndarray) -> tuple[float, float] | None:
    """``(period_s, phase_s)`` of the clock a held temperature changes on (module docstring), else ``None``."""
    t, values = np.asarray(time_s, float), np.asarray(temperature_C, float)
    if t.size < 2 * MIN_ROWS:
        return None
    changed = t[np.flatnonzero(np.diff(values) != 0) + 1]
    if changed.size < MIN_CHANGES:
        return None
    row = float(np.median(np.diff(t)))
    gaps = np.diff(changed)
    period = float(np.median(gaps[gaps < 1.5 * gaps.min()]))
    period = float(np.median(gaps[(gaps > 0.5 * period) & (gaps < 1.5 * period)]))  # the whole one-period cluster
    if period < 0.5 * MIN_ROWS * row:  # gaps of a row or two: a sensor read on every row
        return None
    for _ in range(3):  # refined over the whole log: its span over the periods its gaps hold
        period = float((changed[-1] - changed[0]) / np.maximum(np.round(gaps / period), 1.0).sum())
    if period < 0.99 * MIN_ROWS * row:
        return None
    tolerance = 1.01 * row + 0.01 * period
    offset = changed - changed[0]
    residual = offset - period * np.round(offset / period)
    phase = float(np.median(residual))
    if np.mean(np.abs(residual - phase) <= tolerance) < SHARE:
        return None
    return period, float(changed[0] + phase)


def on_updates(time_s: np.ndarray, columns: dict[str, np.ndarray], period_s: float, phase_s: float,
               row_s: float) -> dict[str, np.ndarray]:
    """``columns`` (``temperature`` among them; each a value per row of ``time_s``) read on the grid's instants
    within the log: the temperature as it reads just after each instant, the others averaged over each interval
    (effort, current and velocity as signed root mean squares, :mod:`.align`)."""
    t = np.asarray(time_s, float)
    slack = 1e-6  # of a period: an instant on the log's first or last row is within it
    k = np.arange(np.ceil((t[0] - phase_s) / period_s - slack), np.floor((t[-1] - phase_s) / period_s + slack) + 1)
    grid = np.clip(phase_s + period_s * k, t[0], t[-1])
    after = np.clip(np.searchsorted(t, grid + 1.5 * row_s, side="right") - 1, 0, t.size - 1)
    out = {"time": grid, "temperature": np.asarray(columns["temperature"], float)[after]}
    for name, values in columns.items():
        if name != "temperature":
            out[name] = interval_average(grid, t, np.asarray(values, float), name in ROOT_MEAN_SQUARE)
    return out


def read_on_updates(rows, name: str, source: str, notes: list[str]):
    """One actuator's rows (a frame of :func:`~.validate.from_frame`'s columns) read on its temperature's updates
    when the temperature is held (module docstring), said in ``notes``; else the rows as they are."""
    t = rows["time"].to_numpy(float)
    grid = update_grid(t, rows["temperature"].to_numpy(float))
    if grid is None:
        return rows
    period, phase = grid
    row = float(np.median(np.diff(t)))
    numeric = {c: rows[c].to_numpy(float) for c in rows.columns if c not in ("time", "actuator")}
    out = on_updates(t, numeric, period, phase, row)
    n = out["time"].size
    notes.append(f"{source}: {name}'s temperature holds each reading for about {period / row:.0f} rows: it changes "
                 f"only on a {period:.3g} s clock among rows {row:.3g} s apart, a reading repeated until the next "
                 f"(read row by row it would be half an update late, which a model takes for a lagging sensor); read "
                 f"on its {n} updates, the inputs averaged over each interval")
    out["actuator"] = np.repeat(rows["actuator"].to_numpy()[:1], n)
    return pd.DataFrame({c: out[c] for c in rows.columns})

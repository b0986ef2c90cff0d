"""A temperature held between its updates, read on the updates.

A logger that merges a slow temperature topic (1 Hz) into the rows of a fast one (joint states at 20 Hz or
more) and fills the blanks -- PlotJuggler's CSV export, a pandas ``ffill``, a driver that republishes its last
reading at the control rate -- repeats each reading until the next.  Read row by row, the held value is half
an update period old on average, and a model reads that delay as physics: the 1 Hz temperatures of a plant
with no lagging sensor, filled onto 20 Hz rows and read row by row, walk to ``+ sensor_lag``; read on their
updates, the walk takes no lag (and reads twenty times fewer samples).

**What counts as held.**  A column that changes only on a clock: at least :data:`MIN_CHANGES` changes, an
update period at least :data:`MIN_ROWS` rows long, and at least :data:`SHARE` of its changes within a row
interval (and a hundredth of the period) of one grid of that period laid over the whole log.  An update that
repeats the reading before it is invisible in the values, so the gaps between changes may be any whole number
of periods; it is the grid, one phase over the whole log, that a sensor sampled row by row does not follow: a
quantised temperature changes when it crosses a step, at instants that follow its slope, and a steady ramp's
regular steps drift off any one grid as soon as the slope changes.  A temperature updated irregularly is not
recognised (said in docs/logs.md).

**How it is read.**  Each run between logging pauses on its own clock (a recording resumed restarts it).  The
log's samples become the grid's instants within it (each taking the value the column
shows just after the instant, so an update a row late counts); the inputs are averaged over each interval by
:mod:`.align`'s rule, as for a temperature logged on its own time column.
"""

from __future__ import annotations

import numpy as np

from ..util.lazy import pandas as pd
from .align import ROOT_MEAN_SQUARE, interval_average
from .series import gaps

MIN_CHANGES = 20
MIN_ROWS = 4
SHARE = 0.9


def update_grid(time_s: np.ndarray, temperature_C: np.ndarray) -> tuple[float, float] | None:
    """``(period_s, phase_s)`` of the clock a held temperature changes on (module docstring), else
    ``None``."""
    t, values = np.asarray(time_s, float), np.asarray(temperature_C, float)
    if t.size < 2 * MIN_ROWS:
        return None
    changed = np.flatnonzero(np.diff(values) != 0) + 1
    # more changes than a held column has
    if changed.size < MIN_CHANGES or changed.size > 2 * t.size / MIN_ROWS:
        return None
    changed = t[changed]
    row = float(np.median(np.diff(t)))
    spacing = np.diff(changed)
    period = float(np.median(spacing[spacing < 1.5 * spacing.min()]))
    cluster = (spacing > 0.5 * period) & (spacing < 1.5 * period)  # the whole one-period cluster
    period = float(np.median(spacing[cluster]))
    if period < 0.5 * MIN_ROWS * row:  # changes a row or two apart: a sensor read on every row
        return None
    for _ in range(3):  # refined over the whole log: its span over the periods its changes are apart
        period = float((changed[-1] - changed[0]) / np.maximum(np.round(spacing / period), 1.0).sum())
    # at least MIN_ROWS rows an update, counted on the log's mean interval where it is the shorter: the median
    # of jittered intervals sits above their mean by chance (4 rows an update at 0.28 of a row's jitter: 1 %
    # above)
    if period < 0.99 * MIN_ROWS * min(row, (t[-1] - t[0]) / (t.size - 1)):
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
    """``columns`` (``temperature`` among them; each a value per row of ``time_s``) read on the grid's
    instants within the log: the temperature as it reads just after each instant, the others averaged over
    each interval (effort, current and velocity as signed root mean squares, :mod:`.align`)."""
    t = np.asarray(time_s, float)
    slack = 1e-6  # of a period: an instant on the log's first or last row is within it
    k = np.arange(np.ceil((t[0] - phase_s) / period_s - slack),
                  np.floor((t[-1] - phase_s) / period_s + slack) + 1)
    grid = np.clip(phase_s + period_s * k, t[0], t[-1])
    after = np.clip(np.searchsorted(t, grid + 1.5 * row_s, side="right") - 1, 0, t.size - 1)
    out = {"time": grid, "temperature": np.asarray(columns["temperature"], float)[after]}
    for name, values in columns.items():
        if name != "temperature":
            out[name] = interval_average(grid, t, np.asarray(values, float), name in ROOT_MEAN_SQUARE)
    return out


def read_on_updates(rows, name: str, source: str, notes: list[str]):
    """One actuator's rows (a frame of :func:`~.validate.from_frame`'s columns) read on its temperature's
    updates where the temperature is held (module docstring), each run between logging pauses on its own clock
    (a recording resumed restarts it), said in ``notes``; else the rows as they are."""
    t = rows["time"].to_numpy(float)
    cuts = [0, *gaps(t), t.size]
    pieces, found = [], []
    for a, b in zip(cuts[:-1], cuts[1:]):
        piece = rows.iloc[a:b]
        grid = update_grid(t[a:b], piece["temperature"].to_numpy(float))
        if grid is None:
            pieces.append(piece)
            continue
        row = float(np.median(np.diff(t[a:b])))
        numeric = {c: piece[c].to_numpy(float) for c in rows.columns if c not in ("time", "actuator")}
        out = on_updates(t[a:b], numeric, *grid, row)
        out["actuator"] = np.repeat(piece["actuator"].to_numpy()[:1], out["time"].size)
        pieces.append(pd.DataFrame({c: out[c] for c in rows.columns}))
        found.append((grid[0], row, out["time"].size))
    if not found:
        return rows
    period, row = found[0][:2]
    runs = "" if len(cuts) == 2 else f" (in {len(found)} of its {len(cuts) - 1} runs)"
    notes.append(f"{source}: {name}'s temperature holds each reading "
                 f"for about {period / row:.0f} rows{runs}: it "
                 f"changes only on a {period:.3g} s clock among rows "
                 f"{row:.3g} s apart, a reading repeated until the "
                 "next (read row by row it would be half an update "
                 "late, which a model takes for a lagging sensor); "
                 f"read on its {sum(n for *_, n in found)} updates, the inputs averaged over each interval")
    return pieces[0] if len(pieces) == 1 else pd.concat(pieces, ignore_index=True)

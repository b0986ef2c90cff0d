"""Channels on different time bases onto one: the temperature sensor's own samples.

The rule, stated once and used for ROS bags and for wide CSVs with several
time columns alike:

* The aligned log's samples are the temperature sensor's own samples; no
  temperature is interpolated, so no measurement is invented.
* An input's value at temperature sample ``k`` is its average over the
  interval that sample opens, ``[t_k, t_k+1)``: the interval over which the
  model holds it (zero-order hold).  Each input sample holds until the next
  one, and counts for the time it holds within the interval: a sample a few
  microseconds before ``t_k`` (two topics stamped alike but for jitter) counts
  for the interval it almost all lies in, not for the one before.  Effort,
  current and velocity are averaged as signed root mean squares (the sign of
  their mean), so that their squares, which the Joule and speed losses use,
  equal the interval's mean square exactly; a sinusoidal effort does not
  average to zero heat.  Other inputs (ambient, housing temperature, power)
  are plain means.
* An interval holding no input sample holds the input's last value before it
  (a slow input stays held, as the model holds it).
* Temperature samples before an input's first sample or after its last are
  left out (the input is unknown there) and said in the notes; no overlap at
  all is an error.  The last temperature sample keeps the previous interval's
  inputs: the model never uses the inputs of a log's last sample.
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

from ..util.errors import LogError

ROOT_MEAN_SQUARE = ("effort", "current", "velocity")


def interval_average(time_s: np.ndarray, sample_time_s: np.ndarray, values: np.ndarray,
                     root_mean_square: bool) -> np.ndarray:
    """``values`` sampled at ``sample_time_s``, each held until the next sample (zero-order hold), averaged
    over each ``[time_s[k], time_s[k+1])`` by the time each value holds within it.

    ``time_s`` must lie within ``[sample_time_s[0], sample_time_s[-1]]`` (the last sample holds beyond).
    Returns one value per ``time_s``; the last repeats the one before.  An interval one value holds throughout
    gets that value exactly (the average is taken as its first value plus the others' weighted differences).
    """
    s = np.asarray(sample_time_s, float)
    x = np.asarray(values, float)
    t = np.asarray(time_s, float)
    edges = np.union1d(t, s[(s > t[0]) & (s < t[-1])])  # the pieces on which one value holds, in one interval
    starts, length = edges[:-1], np.diff(edges)
    held = x[np.clip(np.searchsorted(s, starts, side="right") - 1, 0, s.size - 1)]
    interval = np.searchsorted(t, starts, side="right") - 1
    n = t.size - 1
    span = np.bincount(interval, weights=length, minlength=n)

    def average(y: np.ndarray) -> np.ndarray:
        first = y[np.searchsorted(interval, np.arange(n))]
        return first + np.bincount(interval, weights=(y - first[interval]) * length, minlength=n) / span

    mean = average(held)
    if root_mean_square:
        mean = np.where(mean < 0.0, -1.0, 1.0) * np.sqrt(np.maximum(average(held * held), 0.0))
    return np.append(mean, mean[-1])


def align(temperature: tuple[np.ndarray, np.ndarray], inputs: Mapping[str, tuple[np.ndarray, np.ndarray]],
          source: str) -> tuple[dict[str, np.ndarray], list[str]]:
    """Put ``inputs`` (channel -> (time s, values)) on the temperature's samples by the module's rule.

    Returns ``({"time": ..., "temperature": ..., channel: ...}, notes)``.
    Raises :class:`LogError` naming the channels when their time spans do not overlap.
    """
    t_T, T = (np.asarray(a, dtype=float) for a in temperature)
    keep = np.ones(t_T.size, dtype=bool)
    for name, (t, x) in inputs.items():
        if len(t) == 0:
            raise LogError(f"{source}: channel {name!r} has no samples; expected a time series of {name}")
        inside = (t_T >= t[0]) & (t_T <= t[-1])
        if not inside.any():
            raise LogError(
                f"{source}: the temperature ({t_T[0]:.6g} s to {t_T[-1]:.6g} s) and {name} ({t[0]:.6g} s to "
                f"{t[-1]:.6g} s) do not overlap in time; expected channels recorded over the same period")
        keep &= inside
    if keep.sum() < 2:
        raise LogError(f"{source}: only {int(keep.sum())} temperature "
                       "sample(s) fall where every input channel has "
                       f"data; expected at least two")
    notes = []
    if not keep.all():
        notes.append(f"{source}: {int((~keep).sum())} temperature "
                     "sample(s) outside the inputs' time span left out "
                     f"(aligned on the temperature's own samples, inputs averaged over each interval)")
    t = t_T[keep]
    out = {"time": t, "temperature": T[keep]}
    for name, (ti, x) in inputs.items():
        out[name] = interval_average(t, np.asarray(ti, dtype=float), np.asarray(x, dtype=float),
                                     name in ROOT_MEAN_SQUARE)
    return out, notes


def series_of(time_s, values, source: str, channel: str, drop_incomplete: bool = False,
              notes: list[str] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """One channel's samples, checked for increasing time.

    Samples without a time stamp hold nothing and are dropped.  A reading
    that is missing or not finite (NaN in a bag's field, a blank cell under a
    time stamp) is refused as in every other format, or with
    ``drop_incomplete`` left out and said in ``notes``.
    """
    t = np.asarray(time_s, dtype=float)
    x = np.asarray(values, dtype=float)
    timed = np.isfinite(t)
    t, x = t[timed], x[timed]
    bad = ~np.isfinite(x)
    if bad.all():
        raise LogError(f"{source}: {channel} has no finite reading "
                       f"({x.size} sample(s), all missing or not finite); "
                       f"expected numbers")
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        if not drop_incomplete:
            raise LogError(f"{source}: {channel} has {int(bad.sum())} "
                           f"missing or non-finite reading(s) of {x.size}, "
                           f"first at its sample {k} (t = {t[k]:g} s); "
                           "expected finite numbers (leave them out with "
                           f"--drop-incomplete)")
        if notes is not None:
            notes.append(f"{source}: {int(bad.sum())} missing or non-finite reading(s) of {channel} left out "
                         f"(--drop-incomplete), first at t = {t[k]:g} s")
        t, x = t[~bad], x[~bad]
    steps = np.diff(t)
    if np.any(steps <= 0):
        k = int(np.flatnonzero(steps <= 0)[0])
        raise LogError(f"{source}: the time of {channel} does not increase at its sample {k + 1} "
                       f"({t[k]:g} s then {t[k + 1]:g} s); expected strictly increasing time in seconds")
    return t, x

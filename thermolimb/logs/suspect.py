"""Readings a sensor cannot have meant: a thermistor pinned at a ceiling, one stuck at a value, a temperature
column in Fahrenheit.

A sensor that saturates reads its ceiling while heat still comes in; one that hangs repeats a value while the
effort moves; both spans would be fitted as if the winding had stopped heating.  :func:`leave_out` finds such
spans in one actuator's samples, says each with its span, and leaves its rows out (the log splits into runs
there, as at a pause), or refuses the actuator when too little is left.  The rules are conservative -- a
reading repeated *exactly* over many samples while the effort moves over most of its range, and left by a jump
of more than one of the sensor's steps (or never left) -- so that a coarse but honest sensor is not caught: at
rest, or on a joint heating slowly (a whole-degree sensor holds one value for ten minutes and then moves by
one degree: the heat that came in was less than a step).  :func:`fahrenheit_note` says when a temperature
column reads like degF beside an ambient in degC.
"""

from __future__ import annotations

import numpy as np

from ..util.errors import LogError

STUCK_MIN_SAMPLES = 200  # a value repeated this many times in a row, at least...
STUCK_MIN_SHARE = 0.25  # ...and over this share of the actuator's samples, while the effort moves
EFFORT_MOVES = 0.5  # the effort in the span covers at least this share of the log's effort range
# ...and the reading leaves it by more than this many of the sensor's steps (or never leaves it)
ONE_STEP = 1.5
CEILING_MIN_SAMPLES = 30  # the maximum held this long, at least...
CEILING_MIN_SHARE = 0.03  # ...and over this share of the samples, with more heat coming in than on average
CEILING_STRETCH = 3  # then every stretch of this many samples at the ceiling is left out
DROPOUT_K = 10.0  # a reading this far from both its neighbours' median, and back: a dropout...
DROPOUT_MAX_SAMPLES = 3  # ...lasting at most this many samples


def _plateaus(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(starts, stops)`` of every run of exactly repeated values, as arrays (a noisy log of millions of
    samples has about as many runs: no Python object per run)."""
    change = np.flatnonzero(np.diff(values) != 0.0) + 1
    return np.concatenate([[0], change]), np.concatenate([change, [values.size]])


def suspect_spans(
    time_s: np.ndarray, temperature_C: np.ndarray, effort: np.ndarray
) -> list[tuple[int, int, str]]:
    """``(start, stop, why)`` of the spans a sensor cannot have meant (module docstring)."""
    n = temperature_C.size
    effort_range = float(np.ptp(effort)) or 1.0
    heat = effort * effort
    spans = []
    top = float(np.max(temperature_C))
    starts, stops = _plateaus(temperature_C)
    lengths = stops - starts
    moves = np.abs(np.diff(temperature_C))
    step = float(np.min(moves[moves > 0])) if np.any(moves > 0) else 0.0  # the sensor's resolution, at most
    at_top = temperature_C[starts] == top
    # a ceiling, once one long plateau at the top shows it, holds every stretch the readings sit on it
    long_at_top = np.flatnonzero(at_top & (lengths >= max(CEILING_MIN_SAMPLES, CEILING_MIN_SHARE * n)))
    # ... and longer than the sensor ever held a value below it: a coarse sensor on a slowly heating joint
    # holds every reading as long as its last, highest one (a whole-degree step every ten minutes), a ceiling
    # does not
    below = int(np.max(lengths[~at_top], initial=0))
    ceiling = any(float(np.mean(heat[starts[i]:stops[i]])) > float(np.mean(heat)) and lengths[i] > below
                  for i in long_at_top)
    pinned = ceiling & at_top & (lengths >= CEILING_STRETCH)
    for i in np.flatnonzero(pinned | (lengths >= max(STUCK_MIN_SAMPLES, STUCK_MIN_SHARE * n))):
        a, b = int(starts[i]), int(stops[i])
        if pinned[i]:
            spans.append((a, b, f"pinned at its highest reading, {top:g} "
                                "degC, while heat came in (a sensor at its "
                                f"ceiling)"))
        elif b < n and abs(temperature_C[b] - temperature_C[a]) <= ONE_STEP * step:
            continue  # left by one step: a slow change the sensor resolves no finer, not a hung sensor
        elif a == 0 and b == n:
            # one reading throughout: a joint that did not warm (the fit says there is nothing to learn)
            continue
        elif float(np.ptp(effort[a:b])) >= EFFORT_MOVES * effort_range:
            spans.append((a, b, f"stuck at {temperature_C[a]:g} degC while the effort moved over "
                                f"{100 * np.ptp(effort[a:b]) / effort_range:.0f} % of its range"))
    spans += [(a, b, "a dropout (a reading far from both its neighbours, and back)") for a, b in
              dropouts(temperature_C, heat)]
    spans += [(a, b, f"held at {temperature_C[a]:g} degC after a "
                     f"jump of more than {DROPOUT_K:g} K and back (a "
                     f"sensor open, shorted or not yet configured reads a fixed value)")
              for a, b in held_away(temperature_C, starts, stops)]
    return sorted(spans)


def held_away(values: np.ndarray, starts: np.ndarray, stops: np.ndarray) -> list[tuple[int, int]]:
    """Plateaus longer than a dropout (more than :data:`DROPOUT_MAX_SAMPLES` readings of exactly one value),
    however long, entered by a jump of more than :data:`DROPOUT_K` and left by one back: the value a sensor
    reads when open, shorted or unconfigured (0, -40, 85, 127 degC...).  What marks one is the jump and the
    return to within half the jump of the reading before it, not the value: a motor that warms to 85 degC and
    sits there was not entered by a jump."""
    n = values.size
    pick = np.flatnonzero((stops - starts > DROPOUT_MAX_SAMPLES) & (starts > 0) & (stops < n))
    if pick.size == 0:
        return []
    a, b = starts[pick], stops[pick]
    before, held, after = values[a - 1], values[a], values[b]
    into, back = held - before, after - held
    away = ((np.abs(into) > DROPOUT_K) & (np.abs(back) > DROPOUT_K) & (np.sign(into) != np.sign(back))
            & (np.abs(after - before) < 0.5 * np.abs(into)))
    return [(int(x), int(y)) for x, y in zip(a[away], b[away])]


def dropouts(values: np.ndarray, heat: np.ndarray) -> list[tuple[int, int]]:
    """Stretches of at most :data:`DROPOUT_MAX_SAMPLES` readings more than :data:`DROPOUT_K` kelvin from the
    readings on both sides of them (a sensor reading 0, a sentinel, or a spike, for a moment).

    A dropout is a discontinuity: the readings are steady up to the jump and steady again after the jump back
    (each of the :data:`DROPOUT_MAX_SAMPLES` steps on either side under half of :data:`DROPOUT_K`).  A winding
    heated by effort pulses moves as fast, but its steps around the largest ones are large too, so it is not
    taken for one.  Nor is a rise while more heat comes in (``heat``, the effort squared, at least twice its
    median around the stretch): at a coarse sampling a short pulse can show as one high reading."""
    n = values.size
    w = DROPOUT_MAX_SAMPLES
    if n < 2 * w + 3:
        return []
    out = []
    after_last = w  # where the next dropout may start
    # only where a reading jumps: a log of millions of samples has few such places
    for k in (np.flatnonzero(np.abs(np.diff(values)) > DROPOUT_K) + 1).tolist():
        if k < after_last or k >= n - w:
            continue
        if _steady(values[max(0, k - w - 1):k]):
            before = float(np.median(values[max(0, k - w):k]))
            for length in range(1, w + 1):
                if k + length >= n:
                    break
                after = float(values[k + length])  # the first reading back
                inside = values[k:k + length]
                steady_after = _steady(values[k + length:k + length + w + 1])
                if abs(after - before) < DROPOUT_K / 2 and np.all(np.abs(inside - before) > DROPOUT_K) \
                        and steady_after and not _heated(values, heat, k, k + length, before):
                    out.append((k, k + length))
                    after_last = k + length + 1
                    break
    return out


def _steady(values: np.ndarray) -> bool:
    return bool(np.all(np.abs(np.diff(values)) < DROPOUT_K / 2))


def _heated(values: np.ndarray, heat: np.ndarray, a: int, b: int, before: float) -> bool:
    """The readings ``a:b`` rose while the heat coming in over the intervals leading to them (an input holds
    from its sample to the next, so reading ``k`` follows ``heat[k - 1]``) was at least twice its median on
    both sides of the stretch."""
    if not np.all(values[a:b] > before):
        return False
    w = DROPOUT_MAX_SAMPLES
    around = np.concatenate([heat[max(0, a - 1 - w):a - 1], heat[b - 1:b - 1 + w]])
    return around.size > 0 and float(np.mean(heat[a - 1:b - 1])) >= 2.0 * float(np.median(around))


DISTURBED_MIN_K = 5.0  # a jump up as the effort steps down at least this large...
DISTURBED_SAMPLES = 3  # ...over this many samples, and faster than the readings ever rose while driven


def disturbed_spans(temperature_C: np.ndarray, effort: np.ndarray) -> list[tuple[int, int, float, float]]:
    """``(start, stop, fall_K, jump_K)`` of each span over which the effort is driven (its magnitude above the
    middle of its range) and the readings jump up as it stops.

    A winding cannot heat by kelvins the moment its heat is taken away, nor faster than it heated while the
    heat came in: readings that do read low while the actuator is driven (a thermocouple or thermistor
    disturbed by the drive's electromagnetic noise), and often fall as it starts.  The jump is the rise of the
    readings' 3-sample median over :data:`DISTURBED_SAMPLES` samples after the span, at least
    :data:`DISTURBED_MIN_K` and more than any such rise within the span; the fall, the reading before the span
    less the lowest of its first quarter (reported, not required).

    Parameters
    ----------
    temperature_C, effort
        One run's readings and effort, sample by sample.

    Returns
    -------
    list of (int, int, float, float)
        The spans' first and one-past-last samples, the fall at the start and the jump at the end (K).
    """
    magnitude = np.abs(np.asarray(effort, float))
    n, w = magnitude.size, DISTURBED_SAMPLES
    if n < 4 * w or not np.ptp(magnitude) > 0:
        return []
    smooth = np.median(np.stack([temperature_C[:-2], temperature_C[1:-1], temperature_C[2:]]), axis=0)
    smooth = np.concatenate([temperature_C[:1], smooth, temperature_C[-1:]])
    driven = magnitude > float(np.min(magnitude)) + 0.5 * float(np.ptp(magnitude))
    edges = np.flatnonzero(np.diff(driven.astype(np.int8))) + 1
    bounds = np.concatenate([[0], edges, [n]])
    out = []
    for a, b in zip(bounds[:-1], bounds[1:]):
        if not driven[a] or b > n - w or b - a < 2 * w:
            continue
        jump = float(smooth[b + w - 1] - smooth[b - 1])
        inside = smooth[a:b]
        fastest = float(np.max(inside[w:] - inside[:-w], initial=0.0))
        if jump >= DISTURBED_MIN_K and jump > fastest:
            fall = float(smooth[a - 1] - np.min(inside[:max(w, (b - a) // 4)])) if a > 0 else 0.0
            out.append((int(a), int(b), fall, jump))
    return out


def leave_out(group, name: str, source: str, notes: list[str], min_samples: int):
    """``group`` (one actuator's rows) without its suspect spans, each said; refused when too little is
    left."""
    t = group["time"].to_numpy()
    spans = suspect_spans(t, group["temperature"].to_numpy(), group["effort"].to_numpy())
    if not spans:
        return group
    keep = np.ones(len(group), bool)
    by_kind: dict[str, list[tuple[int, int]]] = {}
    for a, b, why in spans:
        keep[a:b] = False
        by_kind.setdefault(why, []).append((a, b))
    for why, where in by_kind.items():
        a, b = where[0]
        more = f" and {len(where) - 1} more stretches" if len(where) > 1 else ""
        notes.append(f"{source}: actuator {name!r}: the temperature reading is {why}, from {t[a]:g} s to "
                     f"{t[b - 1]:g} s{more} ({sum(y - x for x, y in where)} "
                     "samples): left out of fitting and "
                     f"validation")
    left = int(keep.sum())
    if left < min_samples:
        raise LogError(f"{source}: actuator {name!r}: after leaving "
                       "out the readings a sensor cannot have meant "
                       f"({len(group) - left} of {len(group)} samples), "
                       f"{left} remain; at least {min_samples} are "
                       f"needed")
    return group[keep]


def fahrenheit_note(temperature_C: np.ndarray, effort: np.ndarray, ambient_C: np.ndarray | None, source: str,
                    name: str) -> str | None:
    """A note when the readings at rest sit near 59-86 (15-30 degC in degF) while a logged ambient in degC
    reads 15-30: the temperature column is likely in degF.  A log that starts under load, with too few
    readings at rest, is judged by its first reading: a winding that starts where the air is in degF, and 30 K
    or more above it in degC (a start from rest, unless the motor was already hot: the note says so)."""
    if ambient_C is None:
        return None
    rest = np.abs(effort) <= 0.05 * (float(np.max(np.abs(effort))) or 1.0)
    air = float(np.median(ambient_C))
    if rest.sum() >= 10:
        at_rest, where, close = float(np.median(temperature_C[rest])), "at rest", 4.0
    else:
        at_rest, where, close = float(temperature_C[0]), "at its first reading", 2.0
    if (59.0 <= at_rest <= 86.0 and 15.0 <= air <= 30.0 and abs((at_rest - 32.0) / 1.8 - air) < close
            and (where == "at rest" or at_rest - air >= 30.0)):
        hot = at_rest - air
        unless = f", unless the winding started {hot:.0f} K above the air" if where != "at rest" else ""
        return (f"{source}: actuator {name!r}: the temperature reads {at_rest:.1f} {where} where the ambient "
                f"reads {air:.1f} degC: it looks like degF ({at_rest:.1f} degF = {(at_rest - 32) / 1.8:.1f} "
                f"degC){unless}; convert it, degC = (degF - 32) / 1.8, or state its unit")
    return None

"""When a temperature reaches a limit: the one answer the monitor, the plant's observer and the forecast give.

``None`` means never: not within the curve (or the horizon) simulated, or, for a first-order model, heading
for a steady state at or below the limit.  Every record the suite writes carries ``None`` (``null`` in JSON)
for it; a text field of a ROS message writes ``inf``.
"""

from __future__ import annotations

import numpy as np


def crossing_s(time_s: np.ndarray, curve_C: np.ndarray, threshold_C: float) -> float | None:
    """The first time ``curve_C`` reaches ``threshold_C``, linearly interpolated between samples; ``None``:
    never."""
    above = np.flatnonzero(np.asarray(curve_C) >= threshold_C)
    if above.size == 0:
        return None
    k = int(above[0])
    if k == 0:
        return float(time_s[0])
    t0, t1, y0, y1 = time_s[k - 1], time_s[k], curve_C[k - 1], curve_C[k]
    return float(t0 + (t1 - t0) * (threshold_C - y0) / (y1 - y0))


def first_order_reach_s(
    temperature_C: float, steady_C: float, rate_per_s: float, limit_C: float
) -> float | None:
    """Time for a first-order response from ``temperature_C`` heading for ``steady_C`` at ``rate_per_s`` (1/s)
    to reach ``limit_C``: 0 when already there, ``None`` when it never does."""
    if temperature_C >= limit_C:
        return 0.0
    if steady_C <= limit_C or rate_per_s <= 0:
        return None
    return float(np.log((steady_C - temperature_C) / (steady_C - limit_C)) / rate_per_s)

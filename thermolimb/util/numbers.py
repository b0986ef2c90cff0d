"""Numbers as a reader writes them."""

from __future__ import annotations

import math


def places3(x: float) -> str:
    """``x`` to three decimal places (a temperature error in K), or to two significant figures where three
    places would show too little of it (a sensor floor of 0.00021 K, not 0.000 K)."""
    return f"{x:.3f}" if not 0.0 < abs(x) < 0.01 else significant(x, 2)


def significant(x: float, digits: int = 2) -> str:
    """``x`` to ``digits`` significant figures as ``format(x, 'g')`` writes it, except that a number between
    ``10**digits`` and a million is written to the unit (``360``, where ``format(360.4, '.2g')`` gives
    ``3.6e+02``; ``8123``, not ``8100``, which would claim digits it does not have)."""
    text = f"{x:.{digits}g}"
    if "e" in text and math.isfinite(x) and 1.0 <= abs(x) < 1e6:
        return f"{x:.0f}"
    return text


def to_microsecond(seconds: float | None) -> float | None:
    """A simulated time to the microsecond, far below any control period: a sum of periods without its
    floating-point noise (19462.76, not 19462.760000000002)."""
    return None if seconds is None else round(float(seconds), 6)


def plus_minus(value: float, stderr: float, digits: int = 3) -> str:
    """``value ± stderr``, the value to ``digits`` and its standard error to two significant figures."""
    return f"{significant(value, digits)} ± {significant(stderr, 2)}"

"""What an output-error fit may reach: each parameter's bounds, narrowed to what the runs it sees can show.

Where a log cannot place a value, a fit wanders along a valley of equal error into physics that does not carry
over to the next run. Two such valleys are closed here:

* **A slow mass slower than the runs.** A time constant with ``within_runs`` (a slow mass's) stays within that
  many times the longest run. Slower, a run shows only the start of the mass's rise, along which its share and
  time constant trade, and the mass's start, placed per run, turns it into a free offset per run.
* **An offset below the ambient.** ``T_offset = T_amb + P_bias R`` (Jorgensen et al., Eq. 5), and the bias
  heat is not negative: where the log carries the ambient and no term redefines the offset
  (``offset_is_ambient``: nor a logged temperature as a boundary, a generated form of a channel minus a
  reference), it stays at most ``OFFSET_MARGIN_K`` (a sensor's calibration, not physics) below the coolest
  logged ambient.

Measured on plant logs richer than the model (``python benchmarks/transfer.py --sources plant``: the X8's
winding, housing and body, 1.4, 24.5 and 10,100 s, with speed losses and copper's coefficient), see
docs/workbench.md.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..model.experience import offset_is_ambient
from ..model.terms import Parameter

OFFSET_MARGIN_K = 10.0  # how far below the coolest logged ambient an offset may sit (a sensor's calibration)


def fit_bounds(params: Sequence[Parameter], terms: Sequence[str], series) -> tuple[np.ndarray, np.ndarray]:
    """``(lower, upper)`` of ``params`` (of the model ``terms``) for a fit on ``series``."""
    lower = np.array([p.lower for p in params])
    upper = np.array([p.upper for p in params])
    longest = max(float(s.duration_s) for s in series)
    ambient = [np.nanmin(s.signals.ambient_C) for s in series if s.signals.ambient_C is not None]
    ambient = [a for a in ambient if np.isfinite(a)]
    for k, p in enumerate(params):
        if p.within_runs is not None and longest > 0.0:
            upper[k] = max(min(upper[k], p.within_runs * longest), p.lower + 1e-6 * (p.upper - p.lower))
        if p.name == "T_offset_C" and ambient and offset_is_ambient(terms):
            lower[k] = max(lower[k], float(min(ambient)) - OFFSET_MARGIN_K)
    return lower, upper

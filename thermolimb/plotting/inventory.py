"""What a figure draws, in words a test can hold a caption to.

Every PNG the suite writes carries, in its ``thermolimb:inventory`` text chunk,
a JSON list of its axes: title and axis labels, each line's label, style,
colour and (for reference lines) the value it marks, shaded spans, the bars'
colours and the error bars.  A caption that promises "the warning (75 °C) dashed" can then be
checked against the figure itself rather than against the code that drew it.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from matplotlib.collections import PolyCollection
from matplotlib.colors import to_hex
from matplotlib.container import BarContainer, ErrorbarContainer
from matplotlib.patches import Polygon, Rectangle

KEY = "thermolimb:inventory"
STYLES = {"-": "solid", "--": "dashed", ":": "dotted", "-.": "dashdot"}


def _constant(values) -> float | None:
    values = np.asarray(values, dtype=float)
    if values.size >= 2 and np.all(np.isfinite(values)) and np.ptp(values) == 0.0:
        return float(values[0])
    return None


def _line(line) -> dict:
    item = {"label": "" if line.get_label().startswith("_") else line.get_label(),
            "style": STYLES.get(line.get_linestyle(), "none"), "color": to_hex(line.get_color())}
    y, x = _constant(line.get_ydata()), _constant(line.get_xdata())
    if y is not None and x is None:
        item["y"] = y
    if x is not None and y is None:
        item["x"] = x
    return item


def _errorbars(ax) -> int:
    """Error bars drawn with a visible extent (a bar of zero length promises nothing)."""
    count = 0
    for container in ax.containers:
        bars = container.errorbar if isinstance(container, BarContainer) else container
        if not isinstance(bars, ErrorbarContainer):
            continue
        for collection in bars.lines[2]:
            count += sum(1 for seg in collection.get_segments() if np.ptp(np.asarray(seg), axis=0).max() > 0)
    return count


def _axes(ax) -> dict:
    bars = [p for c in ax.containers if isinstance(c, BarContainer) for p in c.patches]
    in_bars = {id(p) for p in bars}
    shaded = [p for p in ax.patches if isinstance(p, (Rectangle, Polygon)) and id(p) not in in_bars
              and (p.get_alpha() or 1.0) < 1.0]
    shaded += [c for c in ax.collections if isinstance(c, PolyCollection)]
    return {"title": ax.get_title(), "xlabel": ax.get_xlabel(), "ylabel": ax.get_ylabel(),
            "lines": [_line(line) for line in ax.get_lines()],
            "bars": [{"color": to_hex(p.get_facecolor())} for p in bars],
            "errorbars": _errorbars(ax), "shaded": len(shaded)}


def inventory(fig) -> list[dict]:
    """Each visible axes of ``fig`` as a plain dict (see the module docstring); read from the artists, so
    it costs no drawing."""
    return [_axes(ax) for ax in fig.axes if ax.get_visible() and ax.axison]


def metadata(fig) -> dict[str, str]:
    """The PNG text chunk that carries the inventory."""
    return {KEY: json.dumps(inventory(fig), ensure_ascii=True)}


def read_inventory(path: Path) -> list[dict] | None:
    """The inventory a PNG written by the suite carries (``None`` for other files)."""
    from PIL import Image

    with Image.open(path) as image:
        text = getattr(image, "text", {}) or {}
        return json.loads(text[KEY]) if KEY in text else None

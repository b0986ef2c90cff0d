"""``out/index.html``: one static page with every demo's plots and summary tables."""

from __future__ import annotations

import html
import json
from pathlib import Path

from .atomic import write_text
from .errors import UsageError


def _rows(value, prefix: str = ""):
    """Flatten nested summaries into (key, value) rows."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _rows(v, f"{prefix}.{k}" if prefix else str(k))
    elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
        for i, v in enumerate(value):
            yield from _rows(v, f"{prefix}[{i}]")
    else:
        if isinstance(value, float):
            value = f"{value:.4g}"
        yield prefix, value


def _load(path: Path):
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise UsageError(f"{path} cannot be read as JSON ({exc}); run that demo again") from None


def build_report(out: Path) -> Path:
    """Write ``out/index.html`` from every ``out/<demo>/summary.json`` and PNG."""
    out = Path(out)
    folders = sorted(p.parent for p in out.glob("*/summary.json"))
    if not folders:
        raise UsageError(f"{out}: no demo results (no */summary.json); run `thermolimb demo all --out {out}` first")
    parts = [
        "<!doctype html><html><head><meta charset='utf-8'><title>thermolimb report</title>",
        "<style>body{font-family:sans-serif;max-width:1100px;margin:auto;padding:1em}"
        "table{border-collapse:collapse;font-size:13px}td{border:1px solid #ccc;padding:2px 6px}"
        "img{max-width:100%;border:1px solid #ddd;margin:6px 0}</style></head><body>",
        "<h1>thermolimb report</h1>",
        "<p>Each section is one demo: its plots, then its summary (the same numbers as its summary.json).</p>",
        "<ul>" + "".join(f"<li><a href='#{f.name}'>{html.escape(f.name)}</a></li>" for f in folders) + "</ul>",
    ]
    for folder in folders:
        summary = _load(folder / "summary.json")
        parts.append(f"<h2 id='{folder.name}'>{html.escape(folder.name)}</h2>")
        for png in sorted(folder.glob("*.png")):
            rel = png.relative_to(out).as_posix()
            parts.append(f"<div><img src='{html.escape(rel)}' alt='{html.escape(png.stem)}'></div>")
        details = folder / "details.json"
        if details.is_file():
            summary = {**summary, "details": _load(details)}
        parts.append("<table>")
        for key, value in _rows(summary):
            parts.append(f"<tr><td>{html.escape(key)}</td><td>{html.escape(str(value))}</td></tr>")
        parts.append("</table>")
    parts.append("</body></html>")
    return write_text(out / "index.html", "\n".join(parts))

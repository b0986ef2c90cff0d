"""``out/index.html``: one page a person reads, with every demo's story, headline numbers and figures.

For each demo folder (``out/<demo>/summary.json``): what the demo shows and
what to look at (its :class:`~thermolimb.demo_registry.DemoPage`), its
headline numbers as a small table (quantity, value with unit, what it is
compared with), its figures with captions, and links to the full JSON and,
where the demo wrote one, its interactive page.  The page is written whole
or not at all.
"""

from __future__ import annotations

import html
import json
from pathlib import Path

from .demo_registry import caption, in_tour_order, load_demos
from .model.terms import readable
from .util.atomic import write_text
from .util.errors import UsageError

# the column is as wide as the widest figure the demos draw (1.3k px at 110 dpi), so none is scaled down;
# paragraphs keep a reading width
STYLE = (
    "body{font-family:system-ui,sans-serif;max-width:1320px;margin:auto;padding:1em;line-height:1.45;"
    "color:#222}"
    "p{max-width:1000px}h2{border-top:1px solid #ddd;padding-top:1em;margin-top:2em}"
    "table.headline{border-collapse:collapse;margin:0.6em 0 1em;font-size:14px}"
    "table.headline th,table.headline td{border-bottom:1px solid #ddd;padding:4px 10px;text-align:left;"
    "vertical-align:top}table.headline td.value{font-weight:600;white-space:nowrap}"
    "figure{margin:1em 0}figure img{max-width:100%;border:1px solid #ddd}"
    "pre{background:#f6f6f6;padding:.6em;overflow-x:auto;font-size:13px}"
    "figcaption{color:#555;font-size:14px}.links{font-size:14px}.missing{color:#a40}"
)


def _load(path: Path):
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise UsageError(f"{path} cannot be read as JSON ({exc}); run that demo again") from None


def _finding(demo, summary: dict) -> str:
    try:
        text = demo.page.finding(summary)
    except (KeyError, IndexError, TypeError, ValueError, ZeroDivisionError) as exc:
        return ("<p class='missing'>This run's summary.json does "
                "not have the shape this version of the demo writes "
                f"(missing {html.escape(str(exc))}); run the demo again.</p>")
    return f"<p class='finding'><strong>{html.escape(readable(text))}</strong></p>"


def _headline_table(demo, summary: dict, folder: Path) -> str:
    try:
        rows = demo.page.headline(summary)
    except (KeyError, IndexError, TypeError) as exc:
        return (f"<p class='missing'>{html.escape(str(folder / 'summary.json'))} "
                "does not have the shape this version "
                f"of the demo writes (missing {html.escape(str(exc))}); run the demo again.</p>")
    if not rows:
        return (f"<p class='missing'>{html.escape(str(folder / 'summary.json'))} "
                "holds none of the numbers this demo's "
                f"headline shows; run the demo again.</p>")
    body = "".join(f"<tr><td>{html.escape(readable(q))}</td><td class='value'>{html.escape(readable(v))}</td>"
                   f"<td>{html.escape(readable(c))}</td></tr>" for q, v, c in rows)
    return ("<table class='headline'><thead><tr><th>quantity</th><th>value</th><th>compared "
            "with</th></tr></thead>"
            f"<tbody>{body}</tbody></table>")


def _section(folder: Path, out: Path, demos: dict) -> list[str]:
    summary = _load(folder / "summary.json")
    if not isinstance(summary, dict):
        raise UsageError(f"{folder / 'summary.json'} holds "
                         f"{type(summary).__name__}, not a demo's summary (a JSON "
                         f"object); run that demo again")
    # what the demo returned under "details", written apart by the registry
    if (folder / "details.json").is_file():
        summary = {**summary, "details": _load(folder / "details.json")}
    demo = demos.get(folder.name)
    parts = [f"<h2 id='{html.escape(folder.name)}'>{html.escape(folder.name)}</h2>"]
    if demo is not None:
        parts.append(f"<p><em>{html.escape(demo.description)}</em></p>")
    if demo is not None and demo.page is not None:
        if demo.page.finding is not None:
            parts.append(_finding(demo, summary))
        parts.append(f"<p>{html.escape(demo.page.about)}</p>")
        parts.append(_headline_table(demo, summary, folder))
    page = demo.page if demo is not None else None
    for png in sorted(folder.glob("*.png")):
        rel = png.relative_to(out).as_posix()
        text = caption(page, png.name)
        parts.append(f"<figure><img src='{html.escape(rel)}' alt='{html.escape(text or png.stem)}'>"
                     f"<figcaption>{html.escape(text or png.stem.replace('_', ' '))}</figcaption></figure>")
    for source in sorted(folder.glob("*.py")):  # a term file a diagnosis wrote (--propose), shown as it is
        parts.append(f"<figure><pre><code>{html.escape(source.read_text(encoding='utf-8'))}</code></pre>"
                     f"<figcaption>{html.escape(source.name)}: the "
                     "Python term file the demo wrote, with its fitted "
                     f"values; load it with --terms {html.escape(source.name)}</figcaption></figure>")
    links = [f"<a href='{html.escape(p.relative_to(out).as_posix())}'>{label}</a>"
             for p, label in ((folder / "summary.json", "summary.json (every number)"),
                              (folder / "details.json", "details.json"),
                              (folder / "interactive.html", "interactive figures (zoom)")) if p.is_file()]
    parts.append(f"<p class='links'>{' · '.join(links)}</p>")
    return parts


MARK = "<meta name='generator' content='thermolimb report'>"  # what tells a page this report wrote


def build_report(out: Path) -> Path:
    """Write ``out/index.html`` from every ``out/<demo>/summary.json`` and its figures."""
    out = Path(out)
    by_name = {p.parent.name: p.parent for p in out.glob("*/summary.json")}
    folders = [by_name[name] for name in in_tour_order(by_name)]
    if not folders:
        raise UsageError(f"{out}: no demo results (no */summary.json); "
                         f"run `thermolimb demo all --out {out}` first")
    page = out / "index.html"
    head = page.read_text(encoding="utf-8", errors="replace")[:2000] if page.exists() else MARK
    if MARK not in head and "<title>thermolimb report</title>" not in head:  # (the earlier versions' pages)
        raise UsageError(f"{page} exists and was not written by thermolimb "
                         "report; move it away (the report never "
                         f"replaces a page it did not write)")
    demos = load_demos()
    parts = [
        f"<!doctype html><html><head><meta charset='utf-8'>{MARK}<title>thermolimb report</title>"
        f"<style>{STYLE}</style></head><body>",
        "<h1>thermolimb report</h1>",
        "<p>One section per demo: what it shows and what to look at, its headline numbers, its figures. "
        "Temperatures in °C, temperature errors in K, times in s. Every number is in the demo's "
        "summary.json, linked under its figures.</p>",
        "<p>These are the demos' results as they were run "
        "into this folder: <code>make demo</code> runs every "
        "demo in quick mode (shorter logs, fewer episodes and cells). A full run of one demo: "
        "<code>thermolimb demo NAME --out DIR</code>, then <code>thermolimb report DIR</code>.</p>",
        "<ul>"
        + "".join(
            f"<li><a href='#{html.escape(f.name)}'>{html.escape(f.name)}</a>"
            + (f" — {html.escape(demos[f.name].description)}" if f.name in demos else "")
            + "</li>"
            for f in folders
        )
        + "</ul>",
    ]
    for folder in folders:
        parts += _section(folder, out, demos)
    for name in in_tour_order(n for n in demos if n not in by_name and demos[n].missing):
        parts += [f"<h2 id='{html.escape(name)}'>{html.escape(name)}</h2>",
                  f"<p><em>{html.escape(demos[name].description)}</em></p>",
                  "<p class='missing'>Not run here: it needs "
                  f"{html.escape(', '.join(demos[name].missing))}, which "
                  "this environment lacks (<code>pip install "
                  f"'thermolimb[{html.escape(demos[name].extra)}]'</code>, "
                  f"then <code>thermolimb demo {html.escape(name)} "
                  f"--quick --out {html.escape(str(out))}</code> and "
                  "the report again).</p>"]
    parts.append("</body></html>")
    return write_text(page, "\n".join(parts))

"""Hold a figure's caption to what the figure draws (its PNG inventory, see thermolimb.plotting.inventory).

A caption's promises are read with a small, explicit vocabulary; each returns
the broken promises as sentences, so a failing test says what the reader was
told and did not get.  Words outside the vocabulary promise nothing checkable, and a sentence that
makes its promise conditional ("± std bars when two or more episodes ran")
is not held to it: the figure states the condition (its n) itself.
"""

from __future__ import annotations

import re

COLOURS = {"black": ("#000000", "#333333", "#222222"), "red": ("#d62728", "#ff0000", "#cc0000", "#b22222"),
           "grey": ("#808080", "#999999", "#666666", "#7f7f7f", "#b3b3b3")}
STYLE_WORDS = {"dashed": "dashed", "dotted": "dotted"}
CODE_NAME = re.compile(r"\b[a-z][a-zA-Z0-9]*_[a-zA-Z0-9_]+\b")


def _lines(axes):
    return [line for ax in axes for line in ax["lines"]]


def _style(caption, axes):
    broken = []
    for word, style in STYLE_WORDS.items():
        if re.search(rf"\b{word}\b", caption) and not any(line["style"] == style for line in _lines(axes)):
            broken.append(f"the caption says {word!r} but no line is drawn {style}")
    return broken


def _reference_temperatures(caption, axes):
    """'the warning (75 °C) ... dashed': a horizontal line at 75 on an axis in °C, in the promised style."""
    broken = []
    for sentence in re.split(r"(?<=[.;])\s", caption):
        styles = [s for w, s in STYLE_WORDS.items() if re.search(rf"\b{w}\b", sentence)]
        for value in re.findall(r"(-?\d+(?:\.\d+)?)\s*°C", sentence):
            marks = [line for ax in axes if "°C" in ax["ylabel"] for line in ax["lines"]
                     if "y" in line and abs(line["y"] - float(value)) < 1e-6
                     and (not styles or line["style"] in styles)]
            if styles and not marks:
                broken.append(f"the caption promises a {'/'.join(styles)} line at {value} °C; no axis in °C has one")
    return broken


def _colours(caption, axes):
    broken = []
    for word in re.findall(r"\((black|grey)\)", caption):
        drawn = {line["color"] for line in _lines(axes)} | {b["color"] for ax in axes for b in ax["bars"]}
        if not drawn & set(COLOURS[word]):
            broken.append(f"the caption says ({word}) but nothing is drawn {word}")
    return broken


def _error_bars(caption, axes):
    promised = [s for s in re.split(r"(?<=[.;])\s", caption)
                if re.search(r"±\s*(std|σ)|\d?-?σ bars|error bars", s) and not re.search(r"\b(when|if)\b", s)]
    if promised and not any(ax["errorbars"] for ax in axes):
        return ["the caption promises error bars; none with a visible extent is drawn"]
    return []


def _shaded(caption, axes):
    if re.search(r"\bshaded\b", caption) and not any(ax["shaded"] for ax in axes):
        return ["the caption says 'shaded' but nothing is shaded"]
    return []


def broken_promises(caption: str, axes: list[dict]) -> list[str]:
    """Every promise of ``caption`` that the figure described by ``axes`` does not keep."""
    checks = (_style, _reference_temperatures, _colours, _error_bars, _shaded)
    return [b for check in checks for b in check(caption, axes)]


def code_names(axes: list[dict]) -> list[str]:
    """Axis labels that show a raw identifier (``betaR_K_per_effort2``) instead of words."""
    found = []
    for ax in axes:
        for where in ("xlabel", "ylabel"):
            found += [f"{where} {ax[where]!r}" for _ in CODE_NAME.findall(ax[where])[:1]]
    return found

"""What a command prints and writes: JSON, notes on standard error, parameters with their units, the
interactive page, and the files a run wrote."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from ..model.parameter_units import spaced
from ..util.errors import bounded
from ..util.jsonutil import to_jsonable
from ..workbench.flags import said_once


def print_json(obj, file=None) -> None:
    file = file or sys.stdout
    json.dump(to_jsonable(obj), file, indent=2)
    file.write("\n")


def say(note: str) -> None:
    """A note on standard error, its over-long words (a name, a path) cut
    (:func:`~thermolimb.util.errors.bounded`)."""
    print(f"note: {bounded(note)}", file=sys.stderr)


def format_params(report, indent: str = "  ", evidence: bool = True) -> list[str]:
    """What the validation rests on (unless ``evidence`` is false: said once elsewhere), the parameters with
    uncertainty and unit, one per line, then the report's flags and what was set aside."""
    lines = [f"{indent}{report.evidence.sentence()}"] if evidence else []
    lines += [f"{indent}{p.name:26s} {report.model.params[p.name]:12.5g} "
              f"± {report.stderr[p.name]:.2g}{spaced(report.unit(p))}"
             for p in report.model.parameters]
    lines += [f"{indent}! {flag}" for flag in said_once(report.flags)]  # as the JSON's flags_said
    lines += [f"{indent}{set_aside_sentence(a)}" for a in report.set_aside]
    return lines




def set_aside_sentence(entry) -> str:
    """One line for a term set aside or a value held (an entry of a report's ``set_aside``)."""
    if "term" in entry:
        return f"set aside: {entry['term']} ({entry['reason']})"
    return f"held: {entry['parameter']} = {entry['held_at']:.2f} {entry['unit']} ({entry['reason']})"


def html_page(args, title: str):
    """The interactive page ``--html`` asks for, or ``None``."""
    if not getattr(args, "html", None):
        return None
    from ..plotting.interactive import InteractivePage

    return InteractivePage(title, f"thermolimb {args.command} on {', '.join(map(str, args.logs))}.")


def files_in(folder) -> dict:
    """``{path: (size, mtime)}`` of the files in ``folder`` (nothing when ``None`` or absent): what a run
    wrote is what changed."""
    if folder is None or not Path(folder).is_dir():
        return {}
    return {
        p: (p.stat().st_size, p.stat().st_mtime_ns) for p in sorted(Path(folder).iterdir()) if p.is_file()
    }


def say_written(before: dict, folder, also=(), existed=()) -> None:
    """``wrote PATH`` on standard error for each file of ``folder`` that changed since ``before``, and
    ``also``; ``replaced PATH`` for one that was there before (in ``before``, or one of ``existed``)."""
    after = files_in(folder)
    written = [p for p, stamp in after.items() if before.get(p) != stamp] + [Path(p) for p in also]
    earlier = set(before) | {Path(p) for p in existed}
    for path in dict.fromkeys(written):  # a page written into the plots' folder is said once
        print(f"{'replaced' if path in earlier else 'wrote'} {path}", file=sys.stderr)


def existing(*paths) -> list[Path]:
    """Those of ``paths`` (``None`` skipped) that exist now: what a write will replace."""
    return [Path(p) for p in paths if p is not None and Path(p).exists()]

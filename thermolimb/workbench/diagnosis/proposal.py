"""``--propose``: the channel and discovered terms a diagnosis took, written as one Python file of Term
classes."""

from __future__ import annotations

from pathlib import Path

from ...model.generated import module_source
from ...model.terms import TERMS
from ...util.atomic import write_text
from ..validation import FitReport


def write_proposal(path: Path, finals: list[tuple[str, FitReport]]) -> str:
    """The generated terms of each actuator's final model, as one Python file with their fitted values;
    nothing is written when there are none.  Returns the sentence saying which."""
    classes, fitted = {}, []
    for name, report in finals:
        for term in report.model.terms:
            cls = TERMS[term]
            if getattr(cls, "generated", False):
                classes.setdefault(term, cls.source)
                fitted += [f"#   {name}: {p.name} = {report.model.params[p.name]:.6g} ± "
                           f"{float(report.stderr[p.name]):.2g} {report.unit(p)}" for p in cls.parameters]
    if not classes:
        return f"--propose {path}: nothing written: no channel or discovered term is in the final model"
    doc = (f"Terms proposed by `thermolimb diagnose --discover`: {', '.join(classes)}. Load them with "
           f"`--terms {path.name}` and name them in --model; rename a class and its name to keep it.")
    text = module_source(doc, list(classes.values()))
    text = text.replace(
        "\nimport numpy",
        "\n# fitted values (validation scheme of that run):\n" + "\n".join(fitted) + "\n\nimport numpy",
        1,
    )
    write_text(path, text)
    return f"wrote {path}"

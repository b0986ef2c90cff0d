"""Terms written by the suite itself: a channel the log carries, or a form found in the data.

A generated term is Python source first: :func:`term_source` writes a
:class:`~thermolimb.model.terms.Term` subclass from a few :class:`Feature`
rows, and :func:`define` executes that same source to register it.  So the
term a diagnosis fits is, character for character, the one
``thermolimb diagnose --propose FILE`` hands to the user, who can read it,
rename it, keep it and load it again with ``--terms FILE``.

Each feature adds ``c * f`` to the heat balance (a rise in kelvin per unit
of ``f``), or, as a *gain* feature, ``c * f * (T - reference)``: heat that
depends on the winding temperature itself (a conductance that changes with a
fan's duty, a resistance rising with temperature), which enters the model as
a gain on ``T`` so that it stays a first-order linear ODE at every instant.
"""

from __future__ import annotations

import keyword
import re
import textwrap
from dataclasses import dataclass

import numpy as np

from .terms import TERMS, Term

# what a feature's expression may name, and how the generated code reads it
INPUTS = {
    "effort": 's.effort',
    "velocity": 's.channel("velocity")',
    "current": 's.channel("current")',
    "power": 's.channel("power")',
    "ambient": 's.channel("ambient")',
    "housing": 's.channel("housing")',
    "neighbors": 's.channel("neighbors").mean(axis=1)',
}


def input_arrays(s) -> dict:
    """The arrays the names of :data:`INPUTS` stand for, on the signals ``s`` (``None`` for a channel it lacks)."""
    return {"effort": s.effort, "velocity": s.velocity, "current": s.current_A, "power": s.power_W,
            "ambient": s.ambient_C, "housing": s.housing_C,
            "neighbors": None if s.neighbor_temperature_C is None else s.neighbor_temperature_C.mean(axis=1)}


@dataclass(frozen=True)
class Feature:
    """One regressor of a generated term and its coefficient (a model parameter).

    ``expr`` is a NumPy expression in the names of :data:`INPUTS` and of
    extra channels (see :func:`input_name`); ``reference``, for a gain
    feature, an expression or number (``T_offset_C`` for the model's offset).
    ``sign`` is -1 where the coefficient counts cooling (a conductance's
    increase), so that the physical value is positive.
    """

    param: str
    unit: str  # of the coefficient, a template of channel units (K/({velocity})^2.5)
    expr: str
    symbol: str  # the regressor in symbols, for people: |v|^2.5
    words: str  # the regressor in words
    gain: bool = False
    reference: str = "T_offset_C"
    sign: float = 1.0
    lower: float = -np.inf
    upper: float = np.inf
    typical: float = 1.0
    plausible: tuple[float, float] | None = None


def identifier(text: str) -> str:
    """A Python identifier made of ``text`` (lower case, ``_`` for anything else)."""
    name = re.sub(r"\W+", "_", str(text).strip()).strip("_").lower() or "channel"
    if name[0].isdigit() or keyword.iskeyword(name):
        name = "c_" + name
    return name


def input_name(channel: str) -> str:
    """The name an expression uses for the extra channel ``channel``."""
    return "x_" + identifier(channel)


def class_name(name: str) -> str:
    return "".join(part.capitalize() for part in name.split("_")) or "Generated"


HEADER = '''"""{doc}"""

import numpy as np

from thermolimb.model import Parameter, Term, register_term
'''


def module_source(doc: str, classes: list[str]) -> str:
    """A Python module defining the given term classes (each from :func:`term_source`)."""
    doc = textwrap.fill(doc.replace('"', "'").replace("\\", "/"), 108)
    return HEADER.format(doc=doc) + "".join("\n\n" + c for c in classes)


def term_source(name: str, description: str, features: list[Feature], extras: dict[str, str],
                columns: tuple[str, ...], implausible: str | None = None) -> str:
    """The Python source of a registered :class:`Term` class with these features (see :func:`module_source`).

    ``extras``: the extra channels its expressions read, ``{input name: channel}``;
    ``columns``: the log columns it needs; ``implausible``: the body of an
    ``implausible(self, p)`` method, when it has a check beyond its parameters' ranges.
    """
    params = ",\n".join(
        f"        Parameter({f.param!r}, {f.unit!r}, {_number(f.lower)}, {_number(f.upper)}, {f.typical!r},\n"
        f"                  {('coefficient of ' + f.words)!r},\n"
        f"                  {'the channels it reads, varying independently of the effort'!r}"
        + (f", plausible={f.plausible!r}" if f.plausible else "") + ")"
        for f in features)
    reads = []
    used = " ".join(f.expr + " " + f.reference for f in features)
    for key, code in INPUTS.items():
        if re.search(rf"\b{key}\b", used):
            reads.append(f"        {key} = {code}")
    for key, channel in extras.items():
        reads.append(f"        {key} = s.channel({('extra.' + channel)!r})")
    body = ["        rise, gain = 0.0, 0.0"]
    for f in features:
        coef = f'p[{f.param!r}]' if f.sign == 1.0 else f'{f.sign!r} * p[{f.param!r}]'
        if f.gain:
            reference = 'p["T_offset_C"]' if f.reference == "T_offset_C" else f.reference
            body.append(f"        k = {coef} * ({f.expr})  # {f.symbol}")
            body.append(f"        rise, gain = rise - k * ({reference}), gain + k")
        else:
            body.append(f"        rise = rise + {coef} * ({f.expr})  # {f.symbol}")
    body.append("        return rise, gain")
    check = ""
    if implausible:
        check = ("\n    def implausible(self, p):\n" + textwrap.indent(implausible.strip(), " " * 8)
                 + "\n        return super().implausible(p)\n")
    summary = (description[:1].upper() + description[1:]).rstrip(".").replace('"', "'").replace("\\", "/") + "."
    return f'''@register_term
class {class_name(name)}(Term):
    """{summary}"""

    name = {name!r}
    description = {description!r}
    parameters = (
{params},
    )
    columns = {tuple(columns)!r}

    def contribution(self, p, s):
{chr(10).join(reads)}
{chr(10).join(body)}
{check}'''


def _number(value: float) -> str:
    return repr(float(value)) if np.isfinite(value) else ("np.inf" if value > 0 else "-np.inf")


def define(source: str, doc: str, origin: str) -> type[Term]:
    """Execute a term's class source (it registers itself) and mark it as written by the suite, not by a user.

    A generated term takes the place of an earlier one of its name; the
    catalog search (``candidate_models``) does not offer generated terms of
    its own accord, only the diagnosis that generated them does.
    """
    namespace: dict = {}
    exec(compile(module_source(doc, [source]), f"<thermolimb {origin}>", "exec"), namespace)
    cls = next(v for v in namespace.values() if isinstance(v, type) and issubclass(v, Term) and v is not Term)
    cls.generated = True
    cls.source = source
    return TERMS[cls.name]


def load_term_file(path) -> list[str]:
    """Run a Python file of terms (``@register_term`` classes, e.g. one ``diagnose --propose`` wrote); the names
    it registered.  Any error is one sentence naming the file."""
    import runpy
    from pathlib import Path

    from ..util.errors import ModelSpecError

    path = Path(path)
    if not path.is_file():
        raise ModelSpecError(f"--terms {path}: no such file; expected a Python file of terms")
    if path.suffix != ".py":  # refused before anything in it runs: a log or a table given by mistake
        raise ModelSpecError(f"--terms {path}: not a Python file (.py); expected a Python file of terms, such as the "
                             f"one diagnose --propose writes")
    before = {name: cls for name, cls in TERMS.items()}
    try:
        runpy.run_path(str(path), run_name=f"thermolimb_terms_{identifier(path.stem)}")
    except Exception as exc:  # noqa: BLE001 -- a user's file: whatever it raises is reported as what it is
        raise ModelSpecError(f"--terms {path}: the file could not be loaded: {type(exc).__name__}: {exc}") from None
    added = [name for name, cls in TERMS.items() if before.get(name) is not cls]
    if not added:
        raise ModelSpecError(f"--terms {path}: the file registers no term; expected classes decorated with "
                             f"@register_term")
    return added

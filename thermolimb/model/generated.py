"""Terms written by the suite itself: a channel the log carries, or a form found in the data -- as data.

A generated term is a :class:`Spec`: its name, description, the log columns it reads and a few
:class:`Feature` rows, each a regressor from a closed set of forms (:data:`FORMS`: ``|x|^n``, ``x^2``, a
square above a threshold, ``x |effort|``, ...) of one input (a canonical channel or an extra one) times a
coefficient, the model parameter. :func:`define` registers a :class:`GeneratedTerm` built from the spec;
nothing is compiled or executed, so a spec read from a model file someone shared (:mod:`.saved`) cannot run
code.  For people, :func:`term_source` writes the same term as Python source -- ``thermolimb diagnose
--propose FILE`` hands it over to read, rename, keep and load knowingly with ``--terms FILE``.

Each feature adds ``c * f`` to the heat balance (a rise in kelvin per unit of ``f``), or, as a *gain* feature,
``c * f * (T - reference)``: heat that depends on the winding temperature itself (a conductance that changes
with a fan's duty, a resistance rising with temperature), which enters the model as a gain on ``T`` so that it
stays a first-order linear ODE at every instant.
"""

from __future__ import annotations

import keyword
import math
import re
import textwrap
from dataclasses import asdict, dataclass
from typing import Mapping

import numpy as np

from ..util.errors import ModelSpecError
from .terms import TERMS, Parameter, Term, register_term

CANONICAL_INPUTS = ("effort", "velocity", "current", "power", "ambient", "housing", "neighbors")
# a regressor's form: its values from the input's values ``x`` (and the effort), and the same as NumPy source
FORMS = {
    "value": (lambda x, f, e: x, "{x}"),
    "abs_power": (lambda x, f, e: np.abs(x) ** f.power, "np.abs({x}) ** {power!r}"),
    "square": (lambda x, f, e: x**2, "{x} ** 2"),
    "above": (lambda x, f, e: np.maximum(np.abs(x) - f.threshold, 0.0) ** 2,
              "np.maximum(np.abs({x}) - {threshold!r}, 0.0) ** 2"),
    "times_abs_effort": (lambda x, f, e: x * np.abs(e), "{x} * np.abs(effort)"),
    "minus": (lambda x, f, e: x - f.threshold, "{x} - {threshold!r}"),
    "one": (lambda x, f, e: np.ones_like(x), "1.0"),
}


@dataclass(frozen=True)
class Feature:
    """One regressor of a generated term and its coefficient (a model parameter).

    ``input`` is a canonical channel (:data:`CANONICAL_INPUTS`) or ``extra.NAME``; ``form`` one of
    :data:`FORMS` (with its ``power`` or ``threshold``).  ``reference``, for a gain feature: ``T_offset_C``
    (the model's offset), a number of degC, or an input whose values are a temperature.  ``sign`` is -1 where
    the coefficient counts cooling (a conductance's increase), so that the physical value is positive.
    """

    param: str
    unit: str  # of the coefficient, a template of channel units (K/({velocity})^2.5)
    input: str
    form: str
    symbol: str  # the regressor in symbols, for people: |v|^2.5
    words: str  # the regressor in words
    power: float = 1.0
    threshold: float = 0.0
    gain: bool = False
    reference: str = "T_offset_C"
    sign: float = 1.0
    lower: float = -np.inf
    upper: float = np.inf
    typical: float = 1.0
    plausible: tuple[float, float] | None = None

    def values(self, s) -> np.ndarray:
        """The regressor on the signals ``s``."""
        x = _input(s, self.input)
        return np.broadcast_to(np.asarray(FORMS[self.form][0](x, self, s.effort), float), (s.n,))

    def reference_values(self, s, offset_C: float) -> np.ndarray:
        """A gain feature's reference temperature on ``s`` (degC)."""
        if self.reference == "T_offset_C":
            return np.full(s.n, float(offset_C))
        if _is_number(self.reference):
            return np.full(s.n, float(self.reference))
        return np.asarray(_input(s, self.reference), float)


def _input(s, name: str) -> np.ndarray:
    if name == "neighbors":
        return s.neighbor_mean_C
    return s.channel(name)


def _is_number(text: str) -> bool:
    try:
        return math.isfinite(float(text))
    except ValueError:
        return False


@dataclass(frozen=True)
class Spec:
    """A generated term as data: what :func:`define` registers and a model file stores."""

    name: str
    description: str
    columns: tuple[str, ...]
    features: tuple[Feature, ...]
    # the conductance's multiplier 1 + c x must stay positive over the channel's logged range: (param, x min,
    # x max)
    conductance: tuple[str, float, float] | None = None
    # the slow mass (its term's name) whose conductance to ambient the features multiply by ``1 + sum c x``,
    # in place of the winding's: a fan on the housing; such a term adds no heat of its own
    airflow_on: str | None = None

    def to_json(self) -> dict:
        return {
            "name": self.name,
            "description": self.description,
            "columns": list(self.columns),
            "features": [
                {k: (list(v) if isinstance(v, tuple) else _number_out(v)) for k, v in asdict(f).items()}
                for f in self.features
            ],
            "conductance": None if self.conductance is None else list(self.conductance),
            **({"airflow_on": self.airflow_on} if self.airflow_on else {}),
        }

    @classmethod
    def from_json(cls, record, where: str) -> "Spec":
        """A spec from a model file, checked: known forms and inputs, finite numbers, a name of its own."""
        try:
            features = tuple(Feature(**{k: (tuple(v) if k == "plausible" and v is not None else _number_in(v))
                                        for k, v in f.items()}) for f in record["features"])
            conductance = record.get("conductance")
            spec = cls(str(record["name"]), str(record["description"]), tuple(map(str, record["columns"])),
                       features, None if conductance is None else
                       (str(conductance[0]), float(conductance[1]), float(conductance[2])),
                       None if record.get("airflow_on") is None else str(record["airflow_on"]))
        except (KeyError, TypeError, ValueError, IndexError) as exc:
            raise ModelSpecError(f"{where}: a generated term needs name, description, columns and features "
                                 f"({type(exc).__name__}: {exc})") from None
        for f in spec.features:
            inputs = [f.input] + ([f.reference] if f.gain and f.reference != "T_offset_C"
                                  and not _is_number(f.reference) else [])
            bad = [
                i for i in inputs if i not in CANONICAL_INPUTS and not (i.startswith("extra.") and len(i) > 6)
            ]
            if (
                f.form not in FORMS
                or bad
                or not all(math.isfinite(v) for v in (f.power, f.threshold, f.sign))
            ):
                raise ModelSpecError(f"{where}: generated term {spec.name!r}: "
                                     f"feature {f.param!r} is not one this "
                                     f"suite writes (form {f.form!r}, inputs {inputs}); expected a form of "
                                     f"{', '.join(FORMS)} of a channel")
        if spec.airflow_on is not None and spec.airflow_on not in slow_masses():
            raise ModelSpecError(f"{where}: generated term {spec.name!r} changes the conductance of "
                                 f"{spec.airflow_on!r}; expected one of the slow masses "
                                 f"{', '.join(slow_masses())}")
        if not re.fullmatch(r"[a-z_][a-z0-9_]*", spec.name):
            raise ModelSpecError(f"{where}: generated term name {spec.name!r} is not an identifier")
        return spec


def _number_out(v):
    return v if not isinstance(v, float) or math.isfinite(v) else ("inf" if v > 0 else "-inf")


def _number_in(v):
    return float(v) if v in ("inf", "-inf") else v


class GeneratedTerm(Term):
    """A term built from a :class:`Spec` (:func:`define`): its heat and gain from the spec's features."""

    spec: Spec
    generated = True

    def contribution(self, p, s):
        rise, gain = 0.0, 0.0
        if self.spec.airflow_on:
            return rise, gain
        for f in self.spec.features:
            k = f.sign * p[f.param] * f.values(s)
            if f.gain:
                rise, gain = rise - k * f.reference_values(s, p["T_offset_C"]), gain + k
            else:
                rise = rise + k
        return rise, gain

    # none at all, not an array of zeros: the mass's still-air recursion is kept
    def airflow_gain(self, p, s):
        moving = [f for f in self.spec.features if p[f.param]] if self.spec.airflow_on else []
        return sum(p[f.param] * f.values(s) for f in moving) if moving else 0.0

    def implausible(self, p, units=None):
        if self.spec.conductance is not None:
            param, low, high = self.spec.conductance
            worst = min(1.0 + p[param] * low, 1.0 + p[param] * high)
            if worst <= 0.0:
                return (f"the conductance {_of(self.spec)} would be "
                        f"negative ({worst:.2f} of its value at the "
                        f"channel's zero)")
        return super().implausible(p, units)




def slow_masses() -> dict[str, str]:
    """The catalog's slow masses (terms that are a cascade stage), whose conductance to ambient a generated
    term may change, in words: ``{"second_node": "the second thermal mass", ...}``."""
    return {name: "the " + (term.label or name).removeprefix("a ") for name, term in TERMS.items()
            if term.stage is not Term.stage}


def _of(spec: Spec) -> str:
    """Whose conductance a spec's conductance feature changes, in words."""
    return "to ambient" if spec.airflow_on is None else f"of {slow_masses()[spec.airflow_on]} to ambient"


def define(spec: Spec) -> type[Term]:
    """Register the term of ``spec`` (taking the place of an earlier generated term of its name; the catalog
    search does not offer generated terms of its own accord, only the diagnosis that generated them does)."""
    parameters = tuple(
        Parameter(
            f.param,
            f.unit,
            f.lower,
            f.upper,
            f.typical,
            f"coefficient of {f.words}",
            "the channels it reads, varying independently of the effort",
            plausible=f.plausible,
        )
        for f in spec.features
    )
    mass = {} if spec.airflow_on is None else {"airflow_on": spec.airflow_on, "requires": (spec.airflow_on,)}
    cls = type(
        class_name(spec.name),
        (GeneratedTerm,),
        {
            "name": spec.name,
            "description": spec.description,
            "parameters": parameters,
            "columns": spec.columns,
            "spec": spec,
            "__doc__": spec.description,
            "__module__": __name__,
            **mass,
        },
    )
    cls.source = term_source(spec)
    return register_term(cls)


def identifier(text: str) -> str:
    """A Python identifier made of ``text`` (lower case, ``_`` for anything else)."""
    name = re.sub(r"\W+", "_", str(text).strip()).strip("_").lower() or "channel"
    if name[0].isdigit() or keyword.iskeyword(name):
        name = "c_" + name
    return name


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


def _variable(name: str) -> str:
    return "x_" + identifier(name.removeprefix("extra.")) if name.startswith("extra.") else name


def term_source(spec: Spec) -> str:
    """The Python source of the term of ``spec`` as a :class:`Term` class (for people; see
    :func:`module_source`)."""
    params = ",\n".join(
        f"        Parameter({f.param!r}, {f.unit!r}, "
        f"{_literal(f.lower)}, {_literal(f.upper)}, {f.typical!r},\n"
        f"                  {('coefficient of ' + f.words)!r},\n"
        f"                  {'the channels it reads, varying independently of the effort'!r}"
        + (f", plausible={f.plausible!r}" if f.plausible else "") + ")"
        for f in spec.features)
    inputs = dict.fromkeys(i for f in spec.features for i in [f.input] + ([f.reference] if f.gain else [])
                           if i in CANONICAL_INPUTS or i.startswith("extra."))
    reads = [
        f"        {_variable(i)} = "
        + ("s.neighbor_mean_C" if i == "neighbors" else "s.effort" if i == "effort" else f"s.channel({i!r})")
        for i in inputs
    ]
    body = ["        rise, gain = 0.0, 0.0"]
    for f in spec.features:
        expr = FORMS[f.form][1].format(x=_variable(f.input), power=f.power, threshold=f.threshold)
        coef = f'p[{f.param!r}]' if f.sign == 1.0 else f'{f.sign!r} * p[{f.param!r}]'
        if f.gain:
            reference = (
                'p["T_offset_C"]'
                if f.reference == "T_offset_C"
                else f.reference
                if _is_number(f.reference)
                else _variable(f.reference)
            )
            body += [f"        k = {coef} * ({expr})  # {f.symbol}", "        rise, gain = rise - "
                                                                     f"k * ({reference}), gain + k"]
        else:
            body.append(f"        rise = rise + {coef} * ({expr})  # {f.symbol}")
    body.append("        return rise, gain")
    method = "contribution(self, p, s)"
    if spec.airflow_on:  # the features multiply a slow mass's conductance; the term adds no heat of its own
        method = "airflow_gain(self, p, s)"
        body = ["        return " + " + ".join(
            f"p[{f.param!r}] * "
            f"({FORMS[f.form][1].format(x=_variable(f.input), power=f.power, threshold=f.threshold)})"
            for f in spec.features) + f"  # {', '.join(f.symbol for f in spec.features)}"]
    check = ""
    if spec.conductance is not None:
        param, low, high = spec.conductance
        check = (f"\n    def implausible(self, p, units=None):\n"
                 f"        worst = min(1.0 + p[{param!r}] * {low!r}, 1.0 + p[{param!r}] * {high!r})\n"
                 f"        if worst <= 0.0:\n"
                 f"            return f\"the conductance {_of(spec)} "
                 f"would be negative ({{worst:.2f}} of its value)\"\n"
                 f"        return super().implausible(p, units)\n")
    mass = (
        f"    airflow_on = {spec.airflow_on!r}\n    requires = ({spec.airflow_on!r},)\n"
        if spec.airflow_on
        else ""
    )
    summary = (
        (spec.description[:1].upper() + spec.description[1:]).rstrip(".").replace('"', "'").replace("\\", "/")
    )
    return f'''@register_term
class {class_name(spec.name)}(Term):
    """{summary}."""

    name = {spec.name!r}
    description = {spec.description!r}
    parameters = (
{params},
    )
    columns = {tuple(spec.columns)!r}
{mass}
    def {method}:
{chr(10).join(reads)}
{chr(10).join(body)}
{check}'''


def _literal(value: float) -> str:
    return repr(float(value)) if np.isfinite(value) else ("np.inf" if value > 0 else "-np.inf")


def load_term_file(path) -> list[str]:
    """Run a Python file of terms (``@register_term`` classes, e.g. one ``diagnose --propose`` wrote): a
    user's own code, run because the user names it; the names it registered.  Any error is one sentence naming
    the file."""
    import runpy
    from pathlib import Path

    path = Path(path)
    if not path.is_file():
        raise ModelSpecError(f"--terms {path}: no such file; expected a Python file of terms")
    if path.suffix != ".py":  # refused before anything in it runs: a log or a table given by mistake
        raise ModelSpecError(f"--terms {path}: not a Python file (.py); "
                             "expected a Python file of terms, such as the "
                             f"one diagnose --propose writes")
    before = {name: cls for name, cls in TERMS.items()}
    try:
        runpy.run_path(str(path), run_name=f"thermolimb_terms_{identifier(path.stem)}")
    except Exception as exc:  # noqa: BLE001 -- a user's file: whatever it raises is reported as what it is
        raise ModelSpecError(
            f"--terms {path}: the file could not be loaded: {type(exc).__name__}: {exc}"
        ) from None
    added = [name for name, cls in TERMS.items() if before.get(name) is not cls]
    if not added:
        raise ModelSpecError(f"--terms {path}: the file registers no term; expected classes decorated with "
                             f"@register_term")
    return added


def specs_of(terms) -> dict[str, dict]:
    """The specs of the generated terms among ``terms``, as a model file stores them."""
    return {
        t: TERMS[t].spec.to_json()
        for t in terms
        if isinstance(TERMS[t], type) and issubclass(TERMS[t], GeneratedTerm)
    }


def define_all(records: Mapping[str, dict], where: str) -> None:
    """Register a model file's generated terms from their specs (data only)."""
    for name, record in records.items():
        spec = Spec.from_json(record, where)
        if spec.name != name:
            raise ModelSpecError(f"{where}: generated term {name!r} holds the spec of {spec.name!r}")
        if name in TERMS and not TERMS[name].generated:
            raise ModelSpecError(f"{where}: generated term {name!r} would "
                                 "take the place of the suite's own term of "
                                 f"that name; expected a name of its own")
        define(spec)

"""The model file: an identified thermal model as a versioned JSON document that users keep and reuse.

``thermolimb fit … --save MODEL.json`` and ``thermolimb diagnose … --auto --save MODEL.json`` write it;
``predict``, ``monitor`` and ``compare --model-file`` read it; from Python, :meth:`ModelFile.load`,
:meth:`ModelFile.save`, :func:`load_model` and :func:`save_model`.

One file holds one or more actuators (:class:`SavedModel`), each with what a forecast's interval needs: the
parameters with their units (the log's) and standard errors, their covariance, the validation figures and
the held-out residual's statistics, the log it came from (name, SHA-256, time span, samples) and the
actuator's limit when known.  The schema is in ``docs/model-file.md``; :func:`from_json` checks it and says in
one sentence what is wrong with a file that does not follow it.

Floats are written by ``json`` with Python's shortest round-trip repr, so a loaded model has bit-identical
parameters and predicts exactly what the fitted one did.  A term the suite generated (a channel's form, a
discovered form) travels as its Python source and is registered again on load, as ``--terms`` would; a
term from a user's own ``--terms`` file must be loaded before the model file is.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np

from ..util.errors import ModelFileError, ModelSpecError, UsageError
from .experience import ambient_shift_K, offset_air
from .generated import specs_of
from .model import ThermalModel, model_parameters
from .parameter_units import NOT_GIVEN
from .terms import TERMS

FORMAT = "thermolimb-model"
VERSION = 2  # 2: generated terms as data (never source), the calibration's ranges; version 1 files read alike
READS = (1, 2)
LIMIT_RANGE_C = (-60.0, 400.0)  # a winding limit, as --limit-C takes it
LARGEST = 1e9  # a parameter more than this many times its typical size is no fit's
# a time constant saved in another unit is converted
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0}
PLAUSIBLE_TIME_S = (1e-2, 1e7)  # no actuator's thermal time constant lies outside (10 ms to 116 days)
RESIDUAL_QUANTILES = (0.5, 0.8, 0.9, 0.95, 0.99)
JACKKNIFE_BLOCKS = 5  # delete-one-block refits for the jackknife covariance (forecast intervals draw from it)
MIN_JACKKNIFE_FITS = 3


@dataclass(frozen=True)
class ResidualStats:
    """The held-out free-run residual (measured − simulated, K) of a fitted model: what an interval needs."""

    samples: int
    span_s: float
    mean_K: float
    rmse_K: float
    abs_quantiles_K: Mapping[str, float]  # "0.9": the 90 % quantile of |residual|
    lag1: float  # lag-1 autocorrelation of the residual
    rise_K: float  # the held-out free run's root-mean-square rise above the model's offset
    # how far a forecast started from a reading is off after each lead (s): per level, a quantile of |error|
    # (K)
    leads_s: tuple[float, ...] = ()
    lead_quantiles_K: Mapping[str, tuple[float, ...]] = field(default_factory=dict)

    @classmethod
    def of(cls, residual_K: np.ndarray, span_s: float, rise_K: float) -> "ResidualStats":
        r = np.asarray(residual_K, float)
        r = r[np.isfinite(r)]
        if r.size < 2:
            raise ValueError(f"residual statistics need at least 2 held-out samples, got {r.size}")
        centred = r - r.mean()
        denom = float(np.dot(centred, centred))
        lag1 = float(np.dot(centred[1:], centred[:-1]) / denom) if denom > 0 else 0.0
        quantiles = np.quantile(np.abs(r), RESIDUAL_QUANTILES)
        return cls(int(r.size), float(span_s), float(r.mean()), float(np.sqrt(np.mean(r * r))),
                   {f"{q:g}": float(v) for q, v in zip(RESIDUAL_QUANTILES, quantiles)}, lag1, float(rise_K))

    def abs_quantile_K(self, level: float) -> float:
        """The ``level`` quantile of |residual|, interpolated between the stored ones (K)."""
        levels = np.array(RESIDUAL_QUANTILES)
        values = np.array([self.abs_quantiles_K[f"{q:g}"] for q in RESIDUAL_QUANTILES])
        return float(np.interp(level, levels, values))

    def lead_error_K(self, level: float, lead_s: np.ndarray) -> np.ndarray | None:
        """The ``level`` quantile of a forecast's error after each of ``lead_s`` seconds from a reading (K), from the
        stored profile (rising from zero at lead 0, held beyond the longest lead seen); ``None`` without one."""
        if not self.leads_s:
            return None
        levels = np.array(RESIDUAL_QUANTILES)
        table = np.array([self.lead_quantiles_K[f"{q:g}"] for q in RESIDUAL_QUANTILES])  # levels x leads
        at_level = np.array([np.interp(level, levels, table[:, k]) for k in range(table.shape[1])])
        return np.interp(np.asarray(lead_s, float), np.r_[0.0, self.leads_s], np.r_[0.0, at_level])

    def to_json(self) -> dict:
        out = {"samples": self.samples, "span_s": self.span_s, "mean_K": self.mean_K, "rmse_K": self.rmse_K,
               "abs_quantiles_K": dict(self.abs_quantiles_K), "lag1": self.lag1, "rise_K": self.rise_K}
        if self.leads_s:
            out.update(leads_s=list(self.leads_s), lead_quantiles_K={k: list(v) for k, v in
                                                                      self.lead_quantiles_K.items()})
        return out


# an effort's units by kind, each in its kind's first unit: a log in one is read in another of its kind
EFFORT_SCALES = ({"N m": 1.0, "Nm": 1.0, "N·m": 1.0, "mN m": 1e-3}, {"A": 1.0, "mA": 1e-3},
                 {"W": 1.0, "mW": 1e-3, "kW": 1e3}, {"N": 1.0, "kN": 1e3})


def effort_factor(model_unit: str, log_unit: str, what: str) -> float:
    """The factor that turns a log's effort in ``log_unit`` into the ``model_unit`` a model heats from: 1
    where they agree or either is not given, the ratio where both are units of one kind (mA and A), and a refusal in
    one sentence where they are not (a current and a torque).  ``what`` names the model for the sentence."""
    if model_unit == log_unit or NOT_GIVEN in (model_unit, log_unit) or not model_unit or not log_unit:
        return 1.0
    for kind in EFFORT_SCALES:
        if model_unit in kind and log_unit in kind:
            return kind[log_unit] / kind[model_unit]
    raise UsageError(f"{what} heats from an effort in {model_unit}; the log gives its effort in {log_unit}, "
                     f"which is no {model_unit} (a torque is no current): refit on this log's effort, or log "
                     f"the one the model was fitted on")


@dataclass(frozen=True)
class SavedModel:
    """One actuator's identified model and what it was identified from."""

    actuator: str
    model: ThermalModel
    stderr: Mapping[str, float]
    covariance: np.ndarray  # parameters in the model's order (RC_s, each term's, T_offset_C)
    jackknife: np.ndarray | None  # the blocked jackknife's covariance, same order (None: not computed)
    units: Mapping[str, str]  # each parameter's unit on the log
    channel_units: Mapping[str, str]
    validation: Mapping[str, float]
    residual: ResidualStats | None  # None: a model saved without held-out data (its intervals say so)
    provenance: Mapping[str, object]
    limit_C: float | None = None  # the winding limit, when known
    method: str = ""
    scheme: str = ""
    # the generated terms' specs (data, never code)
    generated: Mapping[str, dict] = field(default_factory=dict)

    @property
    def offset_air_C(self) -> list[float] | None:
        """The ambient span this model's offset stands for (:func:`~.experience.offset_air`)."""
        ranges = self.provenance.get("ranges") if isinstance(self.provenance, Mapping) else None
        return offset_air(ranges if isinstance(ranges, Mapping) else None)

    def offset_shift_K(self, ambient_C) -> float:
        """How far the offset moves in an air logged as ``ambient_C`` (:func:`~.experience.ambient_shift_K`)."""
        return ambient_shift_K(self.model, self.offset_air_C, ambient_C)

    def to_json(self) -> dict:
        names = [p.name for p in self.model.parameters]
        return {
            "actuator": self.actuator,
            "terms": list(self.model.terms),
            "params": {n: {"value": float(self.model.params[n]), "stderr": float(self.stderr[n]),
                           "unit": self.units[n]} for n in names},
            "covariance": {"order": names, "matrix": np.asarray(self.covariance, float).tolist()},
            "jackknife": None if self.jackknife is None else {"blocks": JACKKNIFE_BLOCKS,
                                                              "matrix": np.asarray(self.jackknife, float).tolist()},
            "channel_units": dict(self.channel_units),
            "validation": {k: float(v) for k, v in self.validation.items()},
            "residual": None if self.residual is None else self.residual.to_json(),
            "provenance": dict(self.provenance),
            "limit_C": self.limit_C,
            "method": self.method,
            "validation_scheme": self.scheme,
            "generated_terms": dict(self.generated),
        }


@dataclass(frozen=True)
class ModelFile:
    """Every actuator's :class:`SavedModel`, by name."""

    actuators: Mapping[str, SavedModel]
    # what loading it has to say (a limit below what its log read, a unit converted)
    notes: tuple[str, ...] = ()

    def __getitem__(self, actuator: str) -> SavedModel:
        if actuator not in self.actuators:
            raise ModelFileError(f"the model file has no actuator {actuator!r}; it has {', '.join(self.actuators)}")
        return self.actuators[actuator]

    def to_json(self) -> dict:
        return {"format": FORMAT, "version": VERSION,
                "actuators": [saved.to_json() for saved in self.actuators.values()]}

    def save(self, path: str | Path) -> Path:
        """Write the file whole or not at all -- and not at all when it would not load (a value outside what its
        parameter can be, from an unconstrained fit): the loader's checks run on what is written."""
        from ..util.atomic import atomic_path

        path = Path(path)
        document = self.to_json()
        from_json(json.loads(json.dumps(document)), str(path))
        with atomic_path(path) as tmp:
            Path(tmp).write_text(json.dumps(document, indent=1, allow_nan=False) + "\n")
        return path

    @classmethod
    def load(cls, path: str | Path) -> "ModelFile":
        path = Path(path)
        try:
            text = path.read_text()
        except FileNotFoundError:
            raise ModelFileError(f"{path}: no such model file; expected a JSON file written by "
                                 f"`thermolimb fit … --save`") from None
        except (OSError, UnicodeDecodeError) as exc:
            raise ModelFileError(f"{path}: cannot read the model file ({exc})") from None
        try:
            document = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ModelFileError(f"{path}: not a JSON model file (line {exc.lineno}: {exc.msg}); expected a file "
                                 f"written by `thermolimb fit … --save`") from None
        except RecursionError:
            raise ModelFileError(f"{path}: its JSON is nested deeper than Python reads; a model file is a "
                                 f"few levels deep (as `thermolimb fit … --save` writes it)") from None
        except ValueError as exc:  # an integer of more digits than Python converts
            raise ModelFileError(f"{path}: it holds a number too long to read ({str(exc).split(';')[0]}); "
                                 f"expected the numbers `thermolimb fit … --save` writes") from None
        return from_json(document, str(path))


def from_json(document, source: str = "model file") -> ModelFile:
    """A :class:`ModelFile` from its JSON document, checked as a log is: its schema, each parameter's unit (converted
    when the suite knows the unit, else refused), values within what each can be, a covariance that is one, no
    actuator twice; one sentence when something does not hold, and :attr:`ModelFile.notes` for what it says."""
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        raise ModelFileError(f"{source}: not a thermolimb model file (expected \"format\": \"{FORMAT}\")")
    version = document.get("version")
    if version not in READS:
        raise ModelFileError(f"{source}: model file version {version!r} is not one this thermolimb reads "
                             f"(it reads versions {', '.join(map(str, READS))}); re-save the model with this version's "
                             f"`fit --save`")
    entries = document.get("actuators")
    if not isinstance(entries, list) or not entries:
        raise ModelFileError(f"{source}: \"actuators\" must be a non-empty list of saved models")
    saved, notes = {}, []
    for i, entry in enumerate(entries):
        one = _saved(entry, f"{source}: actuator {i}", notes)
        if one.actuator in saved:
            raise ModelFileError(f"{source}: actuator {one.actuator!r} is in the file twice; expected each actuator "
                                 f"once")
        saved[one.actuator] = one
    return ModelFile(saved, tuple(notes))


REQUIRED = ("actuator", "terms", "params", "covariance", "jackknife", "channel_units", "validation", "residual", "provenance",
            "limit_C")


def _saved(entry, where: str, notes: list) -> SavedModel:
    if not isinstance(entry, dict):
        raise ModelFileError(f"{where}: expected an object")
    missing = [k for k in REQUIRED if k not in entry]
    if missing:
        raise ModelFileError(f"{where}: missing field{'s' if len(missing) > 1 else ''} {', '.join(missing)}")
    if not isinstance(entry["actuator"], str) or not entry["actuator"].strip():
        raise ModelFileError(f"{where}: \"actuator\" must be a name, got {entry['actuator']!r}")
    where = f"{where.rsplit(':', 1)[0]}: actuator {entry['actuator']!r}"
    if entry.get("term_sources"):
        raise ModelFileError(f"{where}: the file carries Python source for its terms "
                             f"({', '.join(entry['term_sources'])}); a model file is data, and thermolimb never runs "
                             f"code from one: re-save the model with this version, or load the terms you trust with "
                             f"--terms FILE")
    generated = entry.get("generated_terms") or {}
    if not isinstance(generated, dict):
        raise ModelFileError(f"{where}: \"generated_terms\" must map term names to their specs")
    from .generated import define_all

    try:
        define_all(generated, where)
    except ModelSpecError as exc:
        raise ModelFileError(str(exc)) from None
    terms = entry["terms"]
    if not isinstance(terms, list) or not all(isinstance(t, str) for t in terms):
        raise ModelFileError(f"{where}: \"terms\" must be a list of term names")
    unknown = [t for t in terms if t not in TERMS]
    if unknown:
        raise ModelFileError(f"{where}: term {unknown[0]!r} is not registered; load the --terms file that "
                             f"defines it first (a model file names a user's own terms, it never holds their code)")
    parameters = model_parameters(tuple(terms))
    names = [p.name for p in parameters]
    params = entry["params"]
    if not isinstance(params, dict):
        raise ModelFileError(f"{where}: \"params\" must map parameter names to values")
    extra = [n for n in params if n not in names]
    if extra:
        raise ModelFileError(f"{where}: parameter {extra[0]!r} is not one of model {','.join(terms)}'s "
                             f"({', '.join(names)})")
    bad = [n for n in names if not isinstance(params.get(n), dict) or not {"value", "stderr", "unit"} <= set(params[n])]
    if bad:
        raise ModelFileError(f"{where}: parameter {bad[0]} needs \"value\", \"stderr\" and \"unit\"")
    channel_units, validation = entry["channel_units"], entry["validation"]
    if not isinstance(channel_units, dict) or not all(isinstance(u, str) for u in channel_units.values()):
        raise ModelFileError(f"{where}: \"channel_units\" must map each channel to its unit's name, got "
                             f"{channel_units!r}")
    if not isinstance(validation, dict) or not all(_number(v) and np.isfinite(v)
                                                   for v in validation.values()):
        raise ModelFileError(f"{where}: \"validation\" must map each held-out error's name to a number, got "
                             f"{validation!r}")
    negative = [k for k, v in validation.items() if k.endswith("_K") and v < 0]
    if negative:
        raise ModelFileError(f"{where}: \"validation\" {negative[0]} is {validation[negative[0]]!r}; an "
                             f"error in K is zero or more")
    values, stderr, scale = {}, {}, np.ones(len(names))
    for k, p in enumerate(parameters):
        values[p.name], stderr[p.name], scale[k] = _parameter(p, params[p.name], channel_units, where, notes)
    try:
        model = ThermalModel(tuple(terms), values, bounded=False)
    except (ValueError, TypeError) as exc:
        raise ModelFileError(f"{where}: {exc}") from None
    matrix = _covariance(entry["covariance"], names, where, "covariance") * np.outer(scale, scale)
    jack = entry["jackknife"]
    jackknife = None if jack is None else _covariance(jack, names, where, "jackknife") * np.outer(scale, scale)
    stats = _residual(entry["residual"], where)
    limit = entry["limit_C"]
    if limit is not None and (not _number(limit) or not LIMIT_RANGE_C[0] <= limit <= LIMIT_RANGE_C[1]):
        low, high = LIMIT_RANGE_C
        raise ModelFileError(f"{where}: \"limit_C\" must be a number of degC between {low:g} and {high:g} "
                             f"(as --limit-C takes it) or null, got {limit!r}")
    provenance = entry["provenance"] if isinstance(entry["provenance"], dict) else {}
    _check_ranges(provenance.get("ranges"), where)
    if not provenance.get("ranges"):
        notes.append(f"{where}: its provenance holds no ranges of the log it was fitted on: whether a "
                     f"forecast or an audit leaves what the model was identified on cannot be said")
    hottest = provenance.get("hottest_reading_C")
    seen = (provenance.get("ranges") or {}).get("temperature_C") if isinstance(provenance.get("ranges"), dict) else None
    coolest = seen[0] if isinstance(seen, list) and seen and isinstance(seen[0], (int, float)) else None
    if limit is not None and coolest is not None and limit <= coolest:
        raise ModelFileError(f"{where}: its limit, {limit:g} degC, is at or below every reading of the log it was "
                             f"fitted on (the coolest {coolest:g} degC); expected a winding limit above them")
    if limit is not None and isinstance(hottest, (int, float)) and limit < hottest:
        notes.append(f"{where}: its limit, {limit:g} degC, is below the {hottest:g} degC the log it was fitted on "
                     f"read: the actuator was past its limit in its own calibration -- check the limit")
    return SavedModel(str(entry["actuator"]), model, stderr, matrix, jackknife, {n: params[n]["unit"] for n in names},
                      dict(channel_units), dict(validation), stats, dict(provenance),
                      None if limit is None else float(limit), str(entry.get("method", "")),
                      str(entry.get("validation_scheme", "")), dict(generated))


def _number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _parameter(p, record, channel_units, where: str, notes: list) -> tuple[float, float, float]:
    """One parameter's value and standard error in the model's unit, and the factor they were converted by: a unit
    the suite knows is converted (and said), any other refused; a value outside what the parameter can be, refused."""
    value, stderr, unit = record["value"], record["stderr"], record["unit"]
    if any(not _number(v) or not np.isfinite(v) for v in (value, stderr)):
        raise ModelFileError(f"{where}: {p.name} needs a finite value and standard error, got {value!r} ± {stderr!r}")
    if stderr < 0:
        raise ModelFileError(f"{where}: {p.name}'s standard error is negative ({stderr!r}); expected zero or more")
    expected, factor = p.unit_in(channel_units), 1.0
    if unit != expected:
        if p.unit == "s" and unit in TIME_UNITS:
            factor = TIME_UNITS[unit]
            notes.append(f"{where}: {p.name} saved in {unit}, converted to s")
        elif p.unit == "degC" and unit == "K":
            value -= 273.15
            notes.append(f"{where}: {p.name} saved in K, converted to degC")
        else:
            raise ModelFileError(f"{where}: {p.name} is in {unit!r} where its log's channels make it {expected!r}; "
                                 f"expected {expected!r}" + (f" (or {', '.join(TIME_UNITS)})" if p.unit == "s" else
                                                             " (or K)" if p.unit == "degC" else ""))
    value, stderr = float(value) * factor, float(stderr) * factor
    if not p.lower <= value <= p.upper:
        raise ModelFileError(f"{where}: {p.name} = {value:g} {expected} is outside what it can be ({p.lower:g} to "
                             f"{p.upper:g}: {p.description})")
    if p.unit == "s" and value > 0 and not PLAUSIBLE_TIME_S[0] <= value <= PLAUSIBLE_TIME_S[1]:
        raise ModelFileError(f"{where}: {p.name} = {value:g} s is no actuator's time constant (expected "
                             f"{PLAUSIBLE_TIME_S[0]:g} to {PLAUSIBLE_TIME_S[1]:g} s)")
    if abs(value) > LARGEST * max(abs(p.typical), 1.0):
        raise ModelFileError(f"{where}: {p.name} = {value:g} {expected} is no actuator's (more than "
                             f"{LARGEST:g} times its typical size, {p.typical:g}); expected a value a fit "
                             f"can give")
    return value, stderr, factor


def _covariance(record, names: list[str], where: str, key: str) -> np.ndarray:
    """A covariance of the parameters ``names``: their order, finite, symmetric and positive semi-definite."""
    try:
        matrix = np.asarray(record.get("matrix") if isinstance(record, dict) else None, dtype=float)
    except (TypeError, ValueError):
        matrix = np.zeros(0)
    if not isinstance(record, dict) or (key == "covariance" and record.get("order") != names) \
            or matrix.shape != (len(names), len(names)):
        raise ModelFileError(f"{where}: \"{key}\" must hold \"order\" (the parameters {', '.join(names)}) "
                             f"and a {len(names)}x{len(names)} \"matrix\"")
    if not np.all(np.isfinite(matrix)) or not np.allclose(matrix, matrix.T, rtol=1e-6, atol=1e-12):
        raise ModelFileError(f"{where}: \"{key}\" is not a covariance (not finite, or not symmetric)")
    diagonal = np.diag(matrix)
    worst = float(np.linalg.eigvalsh((matrix + matrix.T) / 2)[0]) if matrix.size else 0.0
    if np.any(diagonal < 0) or worst < -1e-9 * max(float(np.max(np.abs(diagonal), initial=0.0)), 1e-300):
        raise ModelFileError(f"{where}: \"{key}\" is not a covariance: a variance below zero "
                             f"({', '.join(n for n, d in zip(names, diagonal) if d < 0) or 'a direction of it'})")
    return matrix


def _residual(residual, where: str) -> ResidualStats | None:
    if residual is None:
        return None
    try:
        stats = ResidualStats(
            int(residual["samples"]), float(residual["span_s"]), float(residual["mean_K"]), float(residual["rmse_K"]),
            {k: float(v) for k, v in residual["abs_quantiles_K"].items()}, float(residual["lag1"]),
            float(residual["rise_K"]), tuple(float(v) for v in residual.get("leads_s", ())),
            {k: tuple(float(x) for x in v) for k, v in residual.get("lead_quantiles_K", {}).items()})
        stats.abs_quantile_K(0.9)
        if stats.leads_s:
            stats.lead_error_K(0.9, np.array([1.0]))
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise ModelFileError(f"{where}: \"residual\" needs samples, span_s, mean_K, rmse_K, lag1, rise_K and "
                             f"abs_quantiles_K at {', '.join(f'{q:g}' for q in RESIDUAL_QUANTILES)} ({exc!r})") from None
    values = [stats.rmse_K, *stats.abs_quantiles_K.values(), *(x for v in stats.lead_quantiles_K.values() for x in v)]
    if not all(np.isfinite(v) and v >= 0 for v in values):
        raise ModelFileError(f"{where}: \"residual\" holds an error that is negative or not finite")
    return stats


def _check_ranges(ranges, where: str) -> None:
    """A file's calibration ranges, which forecasts read: each a ``[low, high]`` pair of finite numbers, low first
    (``dt_s`` one positive number); absent ones are simply not known."""
    if ranges is None:
        return
    if not isinstance(ranges, dict):
        raise ModelFileError(f"{where}: \"provenance\".\"ranges\" must be an object of [low, high] pairs, got "
                             f"{ranges!r}")
    for name, value in ranges.items():
        if name == "dt_s":
            if not (_number(value) and np.isfinite(value) and value > 0):
                raise ModelFileError(f"{where}: \"provenance\".\"ranges\".\"dt_s\" must be a positive number of "
                                     f"seconds, got {value!r}")
        elif not (isinstance(value, list) and len(value) == 2 and all(_number(v) and np.isfinite(v) for v in value)
                  and value[0] <= value[1]):
            raise ModelFileError(f"{where}: \"provenance\".\"ranges\".\"{name}\" must be [low, high], two finite "
                                 f"numbers with low first, got {value!r}")


def provenance(paths: Sequence[str | Path], series) -> dict:
    """Where a model came from: the log files (name, SHA-256), the time span and samples it was identified on, the
    hottest reading, and the ranges of its inputs (what a forecast beyond them is said to extrapolate from)."""
    files = []
    for path in paths:
        path = Path(path)
        digest = hashlib.sha256()
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                digest.update(block)
        files.append({"name": path.name, "sha256": digest.hexdigest()})
    out = {"files": files, "runs": len(series), "samples": int(sum(s.n for s in series)),
           "start_s": float(min(s.time_s[0] for s in series)), "end_s": float(max(s.time_s[-1] for s in series))}
    if series:  # as read: a run moved to the air of those fitted with it (common_air) adds its move back
        temperature = np.concatenate([s.temperature_C + s.signals.air_shift_K for s in series])
        out["hottest_reading_C"] = float(temperature.max())
        ranges = {"temperature_C": [float(temperature.min()), float(temperature.max())],
                  "dt_s": float(np.median(np.concatenate([np.diff(s.time_s) for s in series])))}
        for column, attribute in (("effort", "effort"), ("velocity", "velocity"), ("ambient_C", "ambient_C")):
            values = [getattr(s.signals, attribute) for s in series]
            if all(v is not None for v in values):
                v = np.concatenate(values)
                ranges[column] = [float(v.min()), float(v.max())]
        # the offset's air, and as read
        if "ambient_C" in ranges and any(s.signals.air_shift_K for s in series):
            ranges["offset_air_C"] = ranges["ambient_C"]
            v = np.concatenate([s.signals.ambient_C + s.signals.air_shift_K for s in series])
            ranges["ambient_C"] = [float(v.min()), float(v.max())]
        out["ranges"] = ranges
    return out


def load_model(path, actuator: str | None = None) -> ThermalModel:
    """The model of ``actuator`` (or of the file's only actuator) from a model file; what loading it has to say (a
    unit converted, a limit below its own log's readings) is a warning, each one sentence."""
    import warnings

    saved = ModelFile.load(path)
    for note in saved.notes:
        warnings.warn(note, UserWarning, stacklevel=2)
    if actuator is None:
        if len(saved.actuators) != 1:
            raise ModelFileError(f"{path}: the model file holds {', '.join(saved.actuators)}; name the actuator")
        actuator = next(iter(saved.actuators))
    return saved[actuator].model


def save_model(model: ThermalModel, path, actuator: str = "actuator", limit_C: float | None = None) -> Path:
    """Write ``model`` alone to a model file (no standard errors or held-out residual: ``thermolimb fit --save``
    writes those)."""
    return ModelFile({actuator: bare(model, actuator, limit_C)}).save(path)


def bare(model: ThermalModel, actuator: str, limit_C: float | None = None) -> SavedModel:
    """A :class:`SavedModel` of parameter values alone (no standard errors, no held-out residual)."""
    names = [p.name for p in model.parameters]
    return SavedModel(actuator, model, dict.fromkeys(names, 0.0), np.zeros((len(names), len(names))), None,
                      {p.name: p.unit_in(None) for p in model.parameters}, {}, {}, None,
                      {"files": [], "runs": 0, "samples": 0}, limit_C, generated=specs_of(model.terms))

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

from ..util.errors import ModelFileError, ModelSpecError
from .experience import ambient_shift_K, offset_air
from .file_checks import check_ranges, checked_covariance, checked_parameter, checked_residual, is_number
from .generated import specs_of
from .model import ThermalModel, model_parameters
from .residual_stats import ResidualStats
from .terms import TERMS

FORMAT = "thermolimb-model"
VERSION = 2  # 2: generated terms as data (never source), the calibration's ranges; version 1 files read alike
READS = (1, 2)
LIMIT_RANGE_C = (-60.0, 400.0)  # a winding limit, as --limit-C takes it
# a time constant saved in another unit is converted
JACKKNIFE_BLOCKS = 5  # delete-one-block refits for the jackknife covariance (forecast intervals draw from it)
MIN_JACKKNIFE_FITS = 3


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
        """How far the offset moves in an air logged as ``ambient_C``
        (:func:`~.experience.ambient_shift_K`)."""
        return ambient_shift_K(self.model, self.offset_air_C, ambient_C)

    def to_json(self) -> dict:
        names = [p.name for p in self.model.parameters]
        return {
            "actuator": self.actuator,
            "terms": list(self.model.terms),
            "params": {
                n: {
                    "value": float(self.model.params[n]),
                    "stderr": float(self.stderr[n]),
                    "unit": self.units[n],
                }
                for n in names
            },
            "covariance": {"order": names, "matrix": np.asarray(self.covariance, float).tolist()},
            "jackknife": None
            if self.jackknife is None
            else {"blocks": JACKKNIFE_BLOCKS, "matrix": np.asarray(self.jackknife, float).tolist()},
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
            raise ModelFileError(
                f"the model file has no actuator {actuator!r}; it has {', '.join(self.actuators)}"
            )
        return self.actuators[actuator]

    def to_json(self) -> dict:
        return {"format": FORMAT, "version": VERSION,
                "actuators": [saved.to_json() for saved in self.actuators.values()]}

    def save(self, path: str | Path) -> Path:
        """Write the file whole or not at all -- and not at all when it would not load (a value outside what
        its parameter can be, from an unconstrained fit): the loader's checks run on what is written."""
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
            raise ModelFileError(
                f"{path}: not a JSON model file (line {exc.lineno}: {exc.msg}); expected a file "
                f"written by `thermolimb fit … --save`"
            ) from None
        except RecursionError:
            raise ModelFileError(
                f"{path}: its JSON is nested deeper than Python reads; a model file is a "
                f"few levels deep (as `thermolimb fit … --save` writes it)"
            ) from None
        except ValueError as exc:  # an integer of more digits than Python converts
            raise ModelFileError(
                f"{path}: it holds a number too long to read ({str(exc).split(';')[0]}); "
                f"expected the numbers `thermolimb fit … --save` writes"
            ) from None
        return from_json(document, str(path))


def from_json(document, source: str = "model file") -> ModelFile:
    """A :class:`ModelFile` from its JSON document, checked as a log is: its schema, each parameter's unit
    (converted when the suite knows the unit, else refused), values within what each can be, a covariance that
    is one, no actuator twice; one sentence when something does not hold, and :attr:`ModelFile.notes` for what
    it says."""
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        raise ModelFileError(f"{source}: not a thermolimb model file (expected \"format\": \"{FORMAT}\")")
    version = document.get("version")
    if version not in READS:
        raise ModelFileError(
            f"{source}: model file version {version!r} is not one this thermolimb reads "
            f"(it reads versions {', '.join(map(str, READS))}); re-save the model with this version's "
            f"`fit --save`"
        )
    entries = document.get("actuators")
    if not isinstance(entries, list) or not entries:
        raise ModelFileError(f"{source}: \"actuators\" must be a non-empty list of saved models")
    saved, notes = {}, []
    for i, entry in enumerate(entries):
        one = _saved(entry, f"{source}: actuator {i}", notes)
        if one.actuator in saved:
            raise ModelFileError(
                f"{source}: actuator {one.actuator!r} is in the file twice; expected each actuator once"
            )
        saved[one.actuator] = one
    return ModelFile(saved, tuple(notes))


REQUIRED = (
    "actuator",
    "terms",
    "params",
    "covariance",
    "jackknife",
    "channel_units",
    "validation",
    "residual",
    "provenance",
    "limit_C",
)


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
        raise ModelFileError(
            f"{where}: the file carries Python source for its terms "
            f"({', '.join(entry['term_sources'])}); a model file is data, and thermolimb never runs "
            f"code from one: re-save the model with this version, or load the terms you trust with "
            f"--terms FILE"
        )
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
        raise ModelFileError(
            f"{where}: term {unknown[0]!r} is not registered; load the --terms file that "
            f"defines it first (a model file names a user's own terms, it never holds their code)"
        )
    parameters = model_parameters(tuple(terms))
    names = [p.name for p in parameters]
    params = entry["params"]
    if not isinstance(params, dict):
        raise ModelFileError(f"{where}: \"params\" must map parameter names to values")
    extra = [n for n in params if n not in names]
    if extra:
        raise ModelFileError(f"{where}: parameter {extra[0]!r} is not one of model {','.join(terms)}'s "
                             f"({', '.join(names)})")
    bad = [
        n
        for n in names
        if not isinstance(params.get(n), dict) or not {"value", "stderr", "unit"} <= set(params[n])
    ]
    if bad:
        raise ModelFileError(f"{where}: parameter {bad[0]} needs \"value\", \"stderr\" and \"unit\"")
    channel_units, validation = entry["channel_units"], entry["validation"]
    if not isinstance(channel_units, dict) or not all(isinstance(u, str) for u in channel_units.values()):
        raise ModelFileError(f"{where}: \"channel_units\" must map each channel to its unit's name, got "
                             f"{channel_units!r}")
    if not isinstance(validation, dict) or not all(is_number(v) and np.isfinite(v)
                                                   for v in validation.values()):
        raise ModelFileError(f"{where}: \"validation\" must map each held-out error's name to a number, got "
                             f"{validation!r}")
    negative = [k for k, v in validation.items() if k.endswith("_K") and v < 0]
    if negative:
        raise ModelFileError(f"{where}: \"validation\" {negative[0]} is {validation[negative[0]]!r}; an "
                             f"error in K is zero or more")
    values, stderr, scale = {}, {}, np.ones(len(names))
    for k, p in enumerate(parameters):
        values[p.name], stderr[p.name], scale[k] = checked_parameter(p, params[p.name], channel_units, where,
                                                                     notes)
    try:
        model = ThermalModel(tuple(terms), values, bounded=False)
    except (ValueError, TypeError) as exc:
        raise ModelFileError(f"{where}: {exc}") from None
    matrix = checked_covariance(entry["covariance"], names, where, "covariance") * np.outer(scale, scale)
    jack = entry["jackknife"]
    jackknife = (
        None if jack is None else checked_covariance(jack, names, where, "jackknife") * np.outer(scale, scale)
    )
    stats = checked_residual(entry["residual"], where)
    limit = entry["limit_C"]
    if limit is not None and (not is_number(limit) or not LIMIT_RANGE_C[0] <= limit <= LIMIT_RANGE_C[1]):
        low, high = LIMIT_RANGE_C
        raise ModelFileError(f"{where}: \"limit_C\" must be a number of degC between {low:g} and {high:g} "
                             f"(as --limit-C takes it) or null, got {limit!r}")
    provenance = entry["provenance"] if isinstance(entry["provenance"], dict) else {}
    check_ranges(provenance.get("ranges"), where)
    if not provenance.get("ranges"):
        notes.append(f"{where}: its provenance holds no ranges of the log it was fitted on: whether a "
                     f"forecast or an audit leaves what the model was identified on cannot be said")
    hottest = provenance.get("hottest_reading_C")
    seen = (
        (provenance.get("ranges") or {}).get("temperature_C")
        if isinstance(provenance.get("ranges"), dict)
        else None
    )
    coolest = seen[0] if isinstance(seen, list) and seen and isinstance(seen[0], (int, float)) else None
    if limit is not None and coolest is not None and limit <= coolest:
        raise ModelFileError(
            f"{where}: its limit, {limit:g} degC, is at or below every reading of the log it was "
            f"fitted on (the coolest {coolest:g} degC); expected a winding limit above them"
        )
    if limit is not None and isinstance(hottest, (int, float)) and limit < hottest:
        notes.append(f"{where}: its limit, {limit:g} degC, is below the {hottest:g} degC the log it was "
                     f"fitted on read: the actuator was past its limit in its own calibration -- check "
                     f"the limit")
    return SavedModel(str(entry["actuator"]), model, stderr, matrix, jackknife,
                      {n: params[n]["unit"] for n in names}, dict(channel_units), dict(validation), stats,
                      dict(provenance), None if limit is None else float(limit), str(entry.get("method", "")),
                      str(entry.get("validation_scheme", "")), dict(generated))


def provenance(paths: Sequence[str | Path], series) -> dict:
    """Where a model came from: the log files (name, SHA-256), the time span and samples it was identified on,
    the hottest reading, and the ranges of its inputs (what a forecast beyond them is said to extrapolate
    from)."""
    files = []
    for path in paths:
        path = Path(path)
        digest = hashlib.sha256()
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                digest.update(block)
        files.append({"name": path.name, "sha256": digest.hexdigest()})
    out = {
        "files": files,
        "runs": len(series),
        "samples": int(sum(s.n for s in series)),
        "start_s": float(min(s.time_s[0] for s in series)),
        "end_s": float(max(s.time_s[-1] for s in series)),
    }
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
    """The model of ``actuator`` (or of the file's only actuator) from a model file; what loading it has to
    say (a unit converted, a limit below its own log's readings) is a warning, each one sentence."""
    import warnings

    saved = ModelFile.load(path)
    for note in saved.notes:
        warnings.warn(note, UserWarning, stacklevel=2)
    if actuator is None:
        if len(saved.actuators) != 1:
            raise ModelFileError(
                f"{path}: the model file holds {', '.join(saved.actuators)}; name the actuator"
            )
        actuator = next(iter(saved.actuators))
    return saved[actuator].model


def save_model(model: ThermalModel, path, actuator: str = "actuator", limit_C: float | None = None) -> Path:
    """Write ``model`` alone to a model file (no standard errors or held-out residual: ``thermolimb fit
    --save`` writes those)."""
    return ModelFile({actuator: bare(model, actuator, limit_C)}).save(path)


def bare(model: ThermalModel, actuator: str, limit_C: float | None = None) -> SavedModel:
    """A :class:`SavedModel` of parameter values alone (no standard errors, no held-out residual)."""
    names = [p.name for p in model.parameters]
    return SavedModel(actuator, model, dict.fromkeys(names, 0.0), np.zeros((len(names), len(names))), None,
                      {p.name: p.unit_in(None) for p in model.parameters}, {}, {}, None,
                      {"files": [], "runs": 0, "samples": 0}, limit_C, generated=specs_of(model.terms))

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

from ..util.errors import ModelFileError
from .model import ThermalModel, model_parameters
from .terms import TERMS

FORMAT = "thermolimb-model"
VERSION = 1
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
    # how far a forecast started from a reading is off after each lead (s): per level, a quantile of |error| (K)
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
    term_sources: Mapping[str, str] = field(default_factory=dict)  # generated terms' Python source

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
            "term_sources": dict(self.term_sources),
        }


@dataclass(frozen=True)
class ModelFile:
    """Every actuator's :class:`SavedModel`, by name."""

    actuators: Mapping[str, SavedModel]

    def __getitem__(self, actuator: str) -> SavedModel:
        if actuator not in self.actuators:
            raise ModelFileError(f"the model file has no actuator {actuator!r}; it has {', '.join(self.actuators)}")
        return self.actuators[actuator]

    def to_json(self) -> dict:
        return {"format": FORMAT, "version": VERSION,
                "actuators": [saved.to_json() for saved in self.actuators.values()]}

    def save(self, path: str | Path) -> Path:
        """Write the file whole or not at all."""
        from ..util.atomic import atomic_path

        path = Path(path)
        with atomic_path(path) as tmp:
            Path(tmp).write_text(json.dumps(self.to_json(), indent=1, allow_nan=False) + "\n")
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
        return from_json(document, str(path))


def from_json(document, source: str = "model file") -> ModelFile:
    """A :class:`ModelFile` from its JSON document, its schema checked (one sentence when it does not hold)."""
    if not isinstance(document, dict) or document.get("format") != FORMAT:
        raise ModelFileError(f"{source}: not a thermolimb model file (expected \"format\": \"{FORMAT}\")")
    version = document.get("version")
    if version != VERSION:
        raise ModelFileError(f"{source}: model file version {version!r} is not one this thermolimb reads "
                             f"(it reads version {VERSION}); re-save the model with this version's `fit --save`")
    entries = document.get("actuators")
    if not isinstance(entries, list) or not entries:
        raise ModelFileError(f"{source}: \"actuators\" must be a non-empty list of saved models")
    saved = {}
    for i, entry in enumerate(entries):
        one = _saved(entry, f"{source}: actuator {i}")
        saved[one.actuator] = one
    return ModelFile(saved)


REQUIRED = ("actuator", "terms", "params", "covariance", "jackknife", "channel_units", "validation", "residual", "provenance",
            "limit_C")


def _saved(entry, where: str) -> SavedModel:
    if not isinstance(entry, dict):
        raise ModelFileError(f"{where}: expected an object")
    missing = [k for k in REQUIRED if k not in entry]
    if missing:
        raise ModelFileError(f"{where}: missing field{'s' if len(missing) > 1 else ''} {', '.join(missing)}")
    where = f"{where.rsplit(':', 1)[0]}: actuator {entry['actuator']!r}"
    for name, source in (entry.get("term_sources") or {}).items():
        if name not in TERMS or getattr(TERMS[name], "source", None) != source:
            from .generated import define

            try:
                define(source, "A term saved in a thermolimb model file.", "model file")
            except Exception as exc:  # noqa: BLE001 -- the file's own code: whatever it raises is reported
                raise ModelFileError(f"{where}: the saved term {name!r} does not load ({type(exc).__name__}: "
                                     f"{exc})") from None
    unknown = [t for t in entry["terms"] if t not in TERMS]
    if unknown:
        raise ModelFileError(f"{where}: term {unknown[0]!r} is not registered; load the --terms file that "
                             f"defines it first")
    names = [p.name for p in model_parameters(tuple(entry["terms"]))]
    params = entry["params"]
    bad = [n for n in names if not isinstance(params.get(n), dict) or not {"value", "stderr", "unit"} <= set(params[n])]
    if bad:
        raise ModelFileError(f"{where}: parameter {bad[0]} needs \"value\", \"stderr\" and \"unit\"")
    try:
        model = ThermalModel(tuple(entry["terms"]), {n: params[n]["value"] for n in names}, bounded=False)
    except (ValueError, TypeError) as exc:
        raise ModelFileError(f"{where}: {exc}") from None
    cov = entry["covariance"]
    matrix = np.asarray(cov.get("matrix") if isinstance(cov, dict) else None, dtype=float)
    if not isinstance(cov, dict) or cov.get("order") != names or matrix.shape != (len(names), len(names)):
        raise ModelFileError(f"{where}: \"covariance\" must hold \"order\" (the parameters {', '.join(names)}) "
                             f"and a {len(names)}x{len(names)} \"matrix\"")
    jack = entry["jackknife"]
    jackknife = None if jack is None else np.asarray(jack.get("matrix") if isinstance(jack, dict) else None, float)
    if jackknife is not None and jackknife.shape != matrix.shape:
        raise ModelFileError(f"{where}: \"jackknife\" must be null or hold a {len(names)}x{len(names)} \"matrix\"")
    residual = entry["residual"]
    stats = None
    try:
        stats = None if residual is None else ResidualStats(
            int(residual["samples"]), float(residual["span_s"]), float(residual["mean_K"]), float(residual["rmse_K"]),
            {k: float(v) for k, v in residual["abs_quantiles_K"].items()}, float(residual["lag1"]),
            float(residual["rise_K"]), tuple(float(v) for v in residual.get("leads_s", ())),
            {k: tuple(float(x) for x in v) for k, v in residual.get("lead_quantiles_K", {}).items()})
        None if stats is None else stats.abs_quantile_K(0.9)
    except (KeyError, TypeError, ValueError) as exc:
        raise ModelFileError(f"{where}: \"residual\" needs samples, span_s, mean_K, rmse_K, lag1, rise_K and "
                             f"abs_quantiles_K at {', '.join(f'{q:g}' for q in RESIDUAL_QUANTILES)} ({exc!r})") from None
    limit = entry["limit_C"]
    if limit is not None and not (isinstance(limit, (int, float)) and np.isfinite(limit)):
        raise ModelFileError(f"{where}: \"limit_C\" must be a number of degC or null, got {limit!r}")
    return SavedModel(str(entry["actuator"]), model, {n: float(params[n]["stderr"]) for n in names}, matrix, jackknife,
                      {n: str(params[n]["unit"]) for n in names}, dict(entry["channel_units"]),
                      dict(entry["validation"]), stats, dict(entry["provenance"]),
                      None if limit is None else float(limit), str(entry.get("method", "")),
                      str(entry.get("validation_scheme", "")), dict(entry.get("term_sources") or {}))


def provenance(paths: Sequence[str | Path], series) -> dict:
    """Where a model came from: the log files (name, SHA-256), the time span and samples it was identified on."""
    files = []
    for path in paths:
        path = Path(path)
        digest = hashlib.sha256()
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                digest.update(block)
        files.append({"name": path.name, "sha256": digest.hexdigest()})
    return {"files": files, "runs": len(series), "samples": int(sum(s.n for s in series)),
            "start_s": float(min(s.time_s[0] for s in series)), "end_s": float(max(s.time_s[-1] for s in series))}


def load_model(path, actuator: str | None = None) -> ThermalModel:
    """The model of ``actuator`` (or of the file's only actuator) from a model file."""
    saved = ModelFile.load(path)
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
    sources = {t: TERMS[t].source for t in model.terms if getattr(TERMS[t], "generated", False)}
    return SavedModel(actuator, model, dict.fromkeys(names, 0.0), np.zeros((len(names), len(names))), None,
                      {p.name: p.unit_in(None) for p in model.parameters}, {}, {}, None,
                      {"files": [], "runs": 0, "samples": 0}, limit_C, term_sources=sources)

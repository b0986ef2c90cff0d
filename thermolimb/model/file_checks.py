"""The checks a model file's parts pass when it is read (:func:`.saved.from_json`): each parameter's value,
unit and standard error, a covariance, the held-out residual's statistics and the calibration ranges; each
failure one :class:`~thermolimb.util.errors.ModelFileError` sentence naming where it is and what was
expected."""

from __future__ import annotations

import numpy as np

from ..util.errors import ModelFileError
from .residual_stats import RESIDUAL_QUANTILES, ResidualStats

LARGEST = 1e9  # a parameter more than this many times its typical size is no fit's
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0}
PLAUSIBLE_TIME_S = (1e-2, 1e7)  # no actuator's thermal time constant lies outside (10 ms to 116 days)


def is_number(v) -> bool:
    """A JSON number (not a boolean)."""
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def checked_parameter(p, record, channel_units, where: str, notes: list) -> tuple[float, float, float]:
    """One parameter's value and standard error in the model's unit, and the factor they were converted by: a
    unit the suite knows is converted (and said), any other refused; a value outside what the parameter can
    be, refused."""
    value, stderr, unit = record["value"], record["stderr"], record["unit"]
    if any(not is_number(v) or not np.isfinite(v) for v in (value, stderr)):
        raise ModelFileError(
            f"{where}: {p.name} needs a finite value and standard error, got {value!r} ± {stderr!r}"
        )
    if stderr < 0:
        raise ModelFileError(
            f"{where}: {p.name}'s standard error is negative ({stderr!r}); expected zero or more"
        )
    expected, factor = p.unit_in(channel_units), 1.0
    if unit != expected:
        if p.unit == "s" and unit in TIME_UNITS:
            factor = TIME_UNITS[unit]
            notes.append(f"{where}: {p.name} saved in {unit}, converted to s")
        elif p.unit == "degC" and unit == "K":
            value -= 273.15
            notes.append(f"{where}: {p.name} saved in K, converted to degC")
        else:
            raise ModelFileError(
                f"{where}: {p.name} is in {unit!r} where its log's channels make it {expected!r}; "
                f"expected {expected!r}"
                + (
                    f" (or {', '.join(TIME_UNITS)})"
                    if p.unit == "s"
                    else " (or K)"
                    if p.unit == "degC"
                    else ""
                )
            )
    value, stderr = float(value) * factor, float(stderr) * factor
    if not p.lower <= value <= p.upper:
        raise ModelFileError(
            f"{where}: {p.name} = {value:g} {expected} is outside what it can be ({p.lower:g} to "
            f"{p.upper:g}: {p.description})"
        )
    if p.unit == "s" and value > 0 and not PLAUSIBLE_TIME_S[0] <= value <= PLAUSIBLE_TIME_S[1]:
        raise ModelFileError(f"{where}: {p.name} = {value:g} s is no actuator's time constant (expected "
                             f"{PLAUSIBLE_TIME_S[0]:g} to {PLAUSIBLE_TIME_S[1]:g} s)")
    if abs(value) > LARGEST * max(abs(p.typical), 1.0):
        raise ModelFileError(f"{where}: {p.name} = {value:g} {expected} is no actuator's (more than "
                             f"{LARGEST:g} times its typical size, {p.typical:g}); expected a value a fit "
                             f"can give")
    return value, stderr, factor


def checked_covariance(record, names: list[str], where: str, key: str) -> np.ndarray:
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
        raise ModelFileError(
            f'{where}: "{key}" is not a covariance: a variance below zero '
            f"({', '.join(n for n, d in zip(names, diagonal) if d < 0) or 'a direction of it'})"
        )
    return matrix


def checked_residual(residual, where: str) -> ResidualStats | None:
    if residual is None:
        return None
    try:
        stats = ResidualStats(
            int(residual["samples"]),
            float(residual["span_s"]),
            float(residual["mean_K"]),
            float(residual["rmse_K"]),
            {k: float(v) for k, v in residual["abs_quantiles_K"].items()},
            float(residual["lag1"]),
            float(residual["rise_K"]),
            tuple(float(v) for v in residual.get("leads_s", ())),
            {k: tuple(float(x) for x in v) for k, v in residual.get("lead_quantiles_K", {}).items()},
        )
        stats.abs_quantile_K(0.9)
        if stats.leads_s:
            stats.lead_error_K(0.9, np.array([1.0]))
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise ModelFileError(
            f'{where}: "residual" needs samples, span_s, mean_K, rmse_K, lag1, rise_K and '
            f"abs_quantiles_K at {', '.join(f'{q:g}' for q in RESIDUAL_QUANTILES)} ({exc!r})"
        ) from None
    values = [
        stats.rmse_K,
        *stats.abs_quantiles_K.values(),
        *(x for v in stats.lead_quantiles_K.values() for x in v),
    ]
    if not all(np.isfinite(v) and v >= 0 for v in values):
        raise ModelFileError(f"{where}: \"residual\" holds an error that is negative or not finite")
    return stats


def check_ranges(ranges, where: str) -> None:
    """A file's calibration ranges, which forecasts read: each a ``[low, high]`` pair of finite numbers, low
    first (``dt_s`` one positive number); absent ones are simply not known."""
    if ranges is None:
        return
    if not isinstance(ranges, dict):
        raise ModelFileError(
            f'{where}: "provenance"."ranges" must be an object of [low, high] pairs, got {ranges!r}'
        )
    for name, value in ranges.items():
        if name == "dt_s":
            if not (is_number(value) and np.isfinite(value) and value > 0):
                raise ModelFileError(
                    f'{where}: "provenance"."ranges"."dt_s" must be a positive number of '
                    f"seconds, got {value!r}"
                )
        elif not (
            isinstance(value, list)
            and len(value) == 2
            and all(is_number(v) and np.isfinite(v) for v in value)
            and value[0] <= value[1]
        ):
            raise ModelFileError(
                f'{where}: "provenance"."ranges"."{name}" must be [low, high], two finite '
                f"numbers with low first, got {value!r}"
            )

"""Several models fitted and validated the same way on one log, side by side with their information criteria."""

from __future__ import annotations

from ..identification import IdentifiabilityError
from ..identification.metrics import information_criteria
from .validation import FitReport, Scheme, evaluate


def compare_models(series, models, scheme: Scheme = Scheme(), validate_on=()) -> list[tuple[FitReport, dict]]:
    """Fit and validate each model; returns each report with its AIC and BIC.

    A model this log cannot identify is returned as ``(None, {"model", "error"})``; the others go on.
    """
    out = []
    errors = []
    for model in models:
        try:
            report = evaluate(series, model, scheme, validate_on=validate_on)
        except IdentifiabilityError as exc:
            errors.append(exc)
            out.append((None, {"model": list(model), "error": str(exc)}))
            continue
        out.append((report, information_criteria(report.train_residual_K, len(report.model.params))))
    if len(errors) == len(models):
        raise errors[0]
    return out

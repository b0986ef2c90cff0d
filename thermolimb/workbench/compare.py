"""Several models fitted and validated the same way on one log, side by side with their information
criteria."""

from __future__ import annotations

from typing import Mapping

from ..identification import IdentifiabilityError
from ..identification.metrics import information_criteria
from ..model.model import model_parameters
from ..model.terms import parse_model
from .submodel import check_datasheet
from .validation import FitReport, Scheme, validate_model


def compare_models(series, models, scheme: Scheme = Scheme(),
                   datasheet: Mapping[str, float] | None = None) -> list[tuple[FitReport, dict]]:
    """Fit and validate each model; returns each report with its AIC and BIC.

    A model this log cannot identify is returned as ``(None, {"model", "error"})``; the others go on.
    ``datasheet``: values each model holds where the log cannot identify them (those of its parameters).
    """
    datasheet = dict(datasheet or {})
    check_datasheet(datasheet, *(parse_model(m) for m in models))
    out = []
    errors = []
    for model in models:
        names = {p.name for p in model_parameters(parse_model(model))}
        try:
            report = validate_model(series, model, scheme, reduce=True,
                                    datasheet={k: v for k, v in datasheet.items() if k in names})
        except IdentifiabilityError as exc:
            errors.append(exc)
            out.append((None, {"model": list(model), "error": str(exc)}))
            continue
        out.append((report, information_criteria(report.train_residual_K, len(report.model.params))))
    if len(errors) == len(models):
        raise errors[0]
    return out


def rank_models(fitted: list[tuple[FitReport, dict]]) -> dict:
    """The model with the lowest held-out RMSE, if the validation can carry a ranking (:mod:`.evidence`).

    The evidence is the thinnest of the models' (their held-out samples are the same; the span in time
    constants is judged against the slowest fitted time constant).
    """
    evidence = min((r.evidence for r, _ in fitted), key=lambda e: (e.rankable, not e.thin, e.time_constants))
    best = min(fitted, key=lambda x: x[0].validation["rmse_K"])[0]
    name, rmse = ",".join(best.model.terms), best.validation["rmse_K"]
    if len(fitted) < 2:
        sentence, best_model = evidence.sentence(), None
    elif not evidence.rankable:
        sentence, best_model = f"not ranked: {evidence.sentence()}", None
    else:
        sentence = f"lowest held-out RMSE: {name} ({rmse:.3f} K); {evidence.sentence()}"
        best_model = list(best.model.terms)
    return {
        "best": best_model,
        "verdict": evidence.verdict,
        "evidence": evidence.to_json(),
        "sentence": sentence,
    }

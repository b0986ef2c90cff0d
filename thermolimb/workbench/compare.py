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
            report = evaluate(series, model, scheme, validate_on=validate_on, reduce=True)
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
    return {"best": best_model, "verdict": evidence.verdict, "evidence": evidence.to_json(), "sentence": sentence}

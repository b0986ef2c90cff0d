"""``thermolimb compare``: several models side by side on one log."""

from __future__ import annotations

from pathlib import Path

from ..evaluation import FitReport, Scheme, evaluate
from ..identification import IdentifiabilityError
from ..metrics import information_criteria
from ..model.terms import TERMS, parse_model
from .options import (
    add_html,
    add_log_input,
    add_quiet,
    add_validation,
    for_each_actuator,
    format_params,
    html_page,
    scheme_of,
)
from .types import output_dir


def add_parser(sub):
    p = sub.add_parser(
        "compare", help="compare several models on one log: held-out error, AIC/BIC, parameters, overlay",
        description="Fit each --model on the first --split of the log (or by --cv K folds) and validate by free "
        "run: validation RMSE (K), max error (K), fit %, AIC and BIC on the training residual, parameters.",
    )
    add_log_input(p)
    p.add_argument("--model", action="append", required=True, metavar="TERMS",
                   help=f"a model to compare (repeat the option); terms: {', '.join(TERMS)}")
    add_validation(p)
    p.add_argument("--json", action="store_true", help="print the comparison as one JSON object")
    p.add_argument("--plot", type=output_dir, default=None, metavar="DIR", help="write compare_<actuator>.png into DIR")
    add_html(p)
    add_quiet(p)
    p.set_defaults(func=run)

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


def run(args) -> int:
    models = [parse_model(m) for m in args.model]
    scheme = scheme_of(args)
    page = html_page(args, "thermolimb compare")

    def analyse(name, series, held_out):
        results = compare_models(series, models, scheme, held_out)
        fitted = [(r, ic) for r, ic in results if r is not None]
        if page is not None:
            from ..interactive import temperature_figure, thinning_note

            page.add(f"{name}: measured against each model",
                     temperature_figure([(",".join(r.model.terms), r) for r, _ in fitted], name),
                     "Each model's free run, dotted where fitted and solid on held-out data (shaded); the panels "
                     "share the time axis." + thinning_note(fitted[0][0]))
        if args.plot:
            _plot(fitted, name, Path(args.plot) / f"compare_{name.replace('/', '_')}.png")
        lines = [f"{name}:", f"  {'model':40s} {'RMSE K':>8s} {'max K':>8s} {'fit %':>7s} {'AIC':>11s} {'BIC':>11s}"]
        for r, ic in results:
            if r is None:
                lines.append(f"  {','.join(ic['model']):40s} not identifiable: {ic['error']}")
                continue
            v = r.validation
            lines.append(f"  {','.join(r.model.terms):40s} {v['rmse_K']:8.3f} {v['max_abs_K']:8.3f} "
                         f"{v['fit_percent']:7.1f} {ic['aic']:11.1f} {ic['bic']:11.1f}")
        lines.append(f"  validation: {fitted[0][0].scheme}")
        for r, _ in fitted:
            lines.append(f"  {','.join(r.model.terms)}:")
            lines += format_params(r, indent="    ")
        records = [ic if r is None else {**r.to_json(), **ic} for r, ic in results]
        return {"actuator": name, "models": records}, "\n".join(lines)

    return for_each_actuator(args, analyse, page)


def _plot(results, actuator, path):
    from ..plots import plt, save

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(10, 6), sharex=True, height_ratios=[2, 1])
    first = results[0][0]
    for seg in first.validation_segments:
        top.plot(seg.time_s, seg.measured_C, color="k", lw=1)
    for report, _ in results:
        label = ",".join(report.model.terms)
        for i, seg in enumerate(report.validation_segments):
            line, = top.plot(seg.time_s, seg.simulated_C, lw=1, label=label if i == 0 else None)
            bottom.plot(seg.time_s, seg.measured_C - seg.simulated_C, lw=0.8, color=line.get_color())
    top.set_title(f"{actuator}: measured (black) and each model's free run on held-out data")
    top.set_ylabel("temperature (°C)")
    top.legend(fontsize=8)
    bottom.axhline(0, color="k", lw=0.5)
    bottom.set_ylabel("measured − model (K)")
    bottom.set_xlabel("time (s)")
    save(fig, path)

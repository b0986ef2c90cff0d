"""``thermolimb compare``: several models side by side on one log."""

from __future__ import annotations

from pathlib import Path

from ..model.terms import DEFAULT_MODEL, TERMS, parse_model
from ..util.atomic import file_stem
from ..workbench.compare import compare_models, rank_models
from .options import (
    add_html,
    add_log_input,
    add_quiet,
    add_terms,
    add_validation,
    datasheet_of,
    for_each_actuator,
    format_params,
    html_page,
    load_terms,
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
    add_terms(p)
    p.add_argument("--model", action="append", default=None, metavar="TERMS",
                   help=f"a model to compare (repeat the option; default {','.join(DEFAULT_MODEL)}, the model fit and "
                        f"diagnose start from); terms: {', '.join(TERMS)}")
    add_validation(p)
    p.add_argument("--json", action="store_true", help="print the comparison as one JSON object")
    p.add_argument("--plot", type=output_dir, default=None, metavar="DIR", help="write compare_<actuator>.png into DIR")
    add_html(p)
    add_quiet(p)
    p.set_defaults(func=run, discovers=False)


def run(args) -> int:
    load_terms(args)
    models = [parse_model(m) for m in (args.model or [",".join(DEFAULT_MODEL)])]
    datasheet = datasheet_of(args, *models)
    scheme = scheme_of(args)
    page = html_page(args, "thermolimb compare")

    def analyse(name, series, held_out):
        results = compare_models(series, models, scheme, held_out, datasheet)
        fitted = [(r, ic) for r, ic in results if r is not None]
        if page is not None:
            from ..plotting.interactive import temperature_figure, thinning_note

            page.add(f"{name}: measured against each model",
                     temperature_figure([(",".join(r.model.terms), r) for r, _ in fitted], name),
                     "Each model's free run, dotted where fitted and solid on held-out data (shaded); the panels "
                     "share the time axis." + thinning_note(fitted[0][0]))
        if args.plot:
            from ..plotting.fits import plot_comparison

            plot_comparison(fitted, name, Path(args.plot) / f"compare_{file_stem(name)}.png")
        lines = [f"{name}:", f"  {'model':40s} {'RMSE K':>8s} {'max K':>8s} {'fit %':>7s} {'AIC':>11s} {'BIC':>11s}"]
        for r, ic in results:
            if r is None:
                lines.append(f"  {','.join(ic['model']):40s} not identifiable: {ic['error']}")
                continue
            v = r.validation
            lines.append(f"  {','.join(r.model.terms):40s} {v['rmse_K']:8.3f} {v['max_abs_K']:8.3f} "
                         f"{v['fit_percent']:7.1f} {ic['aic']:11.1f} {ic['bic']:11.1f}")
        lines.append(f"  validation: {fitted[0][0].scheme}")
        ranking = rank_models(fitted)
        if len(fitted) > 1:
            lines.append(f"  {ranking['sentence']}")
        for r, _ in fitted:
            lines.append(f"  {','.join(r.model.terms)}:")
            lines += format_params(r, indent="    ", evidence=len(fitted) == 1)
        records = [ic if r is None else {**r.to_json(), **ic} for r, ic in results]
        return {"actuator": name, "models": records, "ranking": ranking}, "\n".join(lines)

    return for_each_actuator(args, analyse, page)

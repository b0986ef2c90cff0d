"""``thermolimb fit``: identify the thermal model of actuators from logs and validate it."""

from __future__ import annotations

from pathlib import Path

from ..identification import ESTIMATORS
from ..model.terms import DEFAULT_MODEL, TERMS
from ..util.atomic import file_stem
from ..workbench.validation import validate_model
from .options import (
    add_fleet,
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
    run_fleet,
    scheme_of,
)
from .types import output_dir


def add_parser(sub):
    p = sub.add_parser(
        "fit", help="identify the thermal model from logs and validate it by free-run simulation",
        description="Fit the effort-based thermal model on the first --split of each run's time span, then "
        "simulate each run from its first reading through to its end from the inputs alone, scoring the rest. Reports "
        "validation RMSE (K), max absolute error (K), fit % = 100(1 - |y - y_sim| / |y - mean y|) and the "
        "parameters with standard errors in the log's units (RC in s, T_offset in degC, betaR in K/(N m)^2 for "
        "efforts in N m or K/mA^2 for a current logged as effort in mA; a unit the log does not give is said so).",
    )
    add_log_input(p)
    add_terms(p)
    p.add_argument("--model", default=",".join(DEFAULT_MODEL), metavar="TERMS",
                   help=f"comma-separated model terms (default {','.join(DEFAULT_MODEL)}); known: {', '.join(TERMS)}")
    p.add_argument("--method", default="output_error", choices=list(ESTIMATORS),
                   help="output_error (default): free-run error, started from least squares; least_squares: "
                        "Jorgensen et al.'s regression solved directly; jorgensen_gd: Jorgensen et al.'s z-scored gradient descent")
    add_validation(p)
    p.add_argument("--json", action="store_true",
                   help="print one JSON object per actuator (a list when several actuators are fitted)")
    p.add_argument("--plot", type=output_dir, default=None, metavar="DIR", help="write fit_<actuator>.png plots into DIR")
    add_html(p)
    add_fleet(p)
    add_quiet(p)
    p.set_defaults(func=run, discovers=False)


def run(args) -> int:
    load_terms(args)
    datasheet = datasheet_of(args, args.model)
    if args.fleet:
        return run_fleet(args, diagnose=False)
    scheme = scheme_of(args)
    page = html_page(args, "thermolimb fit")

    def analyse(name, series, held_out):
        report = validate_model(series, args.model, scheme, validate_on=held_out, method=args.method, reduce=True,
                          datasheet=datasheet)
        if args.plot:
            from ..plotting.fits import plot_fit

            plot_fit(report, Path(args.plot) / f"fit_{file_stem(name)}.png")
        if page is not None:
            from ..plotting.interactive import temperature_figure, thinning_note

            page.add(f"{name}: measured against the model", temperature_figure([(args.model, report)], name),
                     f"{report.scheme}; validation RMSE {report.validation['rmse_K']:.3f} K." + thinning_note(report))
        return report.to_json(), _describe(report)

    return for_each_actuator(args, analyse, page)


def _describe(report) -> str:
    v, t = report.validation, report.train
    lines = [f"{report.actuator}: model {','.join(report.model.terms)} by {report.method}",
             f"  train       RMSE {t['rmse_K']:.3f} K  max {t['max_abs_K']:.3f} K  fit {t['fit_percent']:.1f} %",
             f"  validation  RMSE {v['rmse_K']:.3f} K  max {v['max_abs_K']:.3f} K  fit {v['fit_percent']:.1f} %"
             f"  ({report.scheme})"]
    return "\n".join(lines + format_params(report))

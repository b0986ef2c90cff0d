"""``thermolimb fit``: identify the thermal model of actuators from logs and validate it."""

from __future__ import annotations

from pathlib import Path

from ..evaluation import cross_validate, fit_and_validate
from ..identification import ESTIMATORS
from ..model.terms import DEFAULT_MODEL, TERMS, parse_model
from .options import add_log_input, add_quiet, for_each_actuator


def add_parser(sub):
    p = sub.add_parser(
        "fit", help="identify the thermal model from logs and validate it by free-run simulation",
        description="Fit the effort-based thermal model on the first --split of each log's time span, then "
        "simulate the rest from the measured temperature at the split with no temperature updates. Reports "
        "validation RMSE (K), max absolute error (K), fit % = 100(1 - |y - y_sim| / |y - mean y|) and the "
        "parameters with standard errors (RC in s, betaR in K/(N m)^2, beta_biasR in K/(N m), T_offset in degC).",
    )
    add_log_input(p)
    p.add_argument("--model", default=",".join(DEFAULT_MODEL), metavar="TERMS",
                   help=f"comma-separated model terms (default {','.join(DEFAULT_MODEL)}); known: {', '.join(TERMS)}")
    p.add_argument("--method", default="output_error", choices=list(ESTIMATORS),
                   help="output_error (default): free-run error, started from least squares; least_squares: "
                        "the seed's regression solved directly; seed_gd: the seed's z-scored gradient descent")
    p.add_argument("--split", type=float, default=0.7, help="fraction of each log's time span used to fit (default 0.7)")
    p.add_argument("--cv", type=int, default=None, metavar="K",
                   help="blocked cross-validation over K contiguous folds instead of the single split")
    p.add_argument("--json", action="store_true",
                   help="print one JSON object per actuator (a list when several actuators are fitted)")
    p.add_argument("--plot", default=None, metavar="DIR", help="write fit_<actuator>.png plots into DIR")
    add_quiet(p)
    p.set_defaults(func=run)


def run(args) -> int:
    parse_model(args.model)

    def analyse(name, series):
        if args.cv:
            report = cross_validate(series, args.model, args.cv, method=args.method)
        else:
            report = fit_and_validate(series, args.model, split=args.split, method=args.method)
        if args.plot:
            from ..plots import plot_fit

            plot_fit(report, Path(args.plot) / f"fit_{name.replace('/', '_')}.png")
        return report.to_json(), _describe(report)

    return for_each_actuator(args, analyse)


def _describe(report) -> str:
    v, t = report.validation, report.train
    lines = [f"{report.actuator}: model {','.join(report.model.terms)} by {report.method}",
             f"  train       RMSE {t['rmse_K']:.3f} K  max {t['max_abs_K']:.3f} K  fit {t['fit_percent']:.1f} %",
             f"  validation  RMSE {v['rmse_K']:.3f} K  max {v['max_abs_K']:.3f} K  fit {v['fit_percent']:.1f} %"]
    for p in report.model.parameters:
        lines.append(f"  {p.name:26s} {report.model.params[p.name]:12.5g} ± {report.stderr[p.name]:.2g} {p.unit}")
    return "\n".join(lines)

"""``thermolimb fit``: identify the thermal model of actuators from logs and validate it."""

from __future__ import annotations

from pathlib import Path

from ..identification import ESTIMATORS
from ..util.atomic import file_stem
from ..workbench.validation import validate_model
from .output import format_params
from .template import LogCommand, Run


class Fit(LogCommand):
    name = "fit"
    help = "identify the thermal model from logs and validate it by free-run simulation"
    description = (
        "Fit the effort-based thermal model on the first --split of each run's time span, then "
        "simulate each run from its first reading through to its "
        "end from the inputs alone, scoring the rest. Reports "
        "validation RMSE (K), max absolute error (K), fit % = 100(1 - |y - y_sim| / |y - mean y|) and the "
        "parameters with standard errors in the log's units "
        "(RC in s, T_offset in degC, betaR in K/(N m)^2 for "
        "efforts in N m or K/mA^2 for a current logged as "
        "effort in mA; a unit the log does not give is said so)."
    )
    model_help = "comma-separated model terms"
    fleet = True
    json_help = "print one JSON object per actuator (a list when several actuators are fitted)"
    plot_help = "write fit_<actuator>.png plots into DIR"
    saves = True

    def add_options(self, p):
        p.add_argument("--method", default="output_error", choices=list(ESTIMATORS),
                       help="output_error (default): free-run error, "
                            "started from least squares; least_squares: "
                            "Jorgensen et al.'s regression solved directly; "
                            "jorgensen_gd: Jorgensen et al.'s z-scored "
                            "gradient descent")

    def analyse(self, run: Run, name, series, scheme):
        args, model = run.args, run.models[0]
        report = validate_model(series, model, scheme, method=args.method, reduce=True,
                                datasheet=run.datasheet)
        run.final[name] = report
        if args.plot:
            from ..plotting.fits import plot_fit

            plot_fit(report, Path(args.plot) / f"fit_{file_stem(name)}.png")
        if run.page is not None:
            from ..plotting.interactive import temperature_figure, thinning_note

            run.page.add(
                f"{name}: measured against the model",
                temperature_figure([(args.model, report)], name),
                f"{report.scheme}; validation RMSE {report.validation['rmse_K']:.3f} K."
                + thinning_note(report),
            )
        return report.to_json(), _describe(report)


add_parser = Fit().add_parser


def _describe(report) -> str:
    v, t = report.validation, report.train
    lines = [f"{report.actuator}: model {','.join(report.model.terms)} by {report.method}",
             f"  train       RMSE {t['rmse_K']:.3f} K  max "
             f"{t['max_abs_K']:.3f} K  fit {t['fit_percent']:.1f} %",
             f"  validation  RMSE {v['rmse_K']:.3f} K  max "
             f"{v['max_abs_K']:.3f} K  fit {v['fit_percent']:.1f} %"
             f"  ({report.scheme})",
             "  (fit % = 100 (1 - ‖measured - model‖ / ‖measured - its mean‖), "
             "norms over the samples: 100 % exact, 0 % no better than the "
             "mean, below 0 worse)"]
    return "\n".join(lines + format_params(report))

"""``thermolimb diagnose``: where does the model fail, which effect is missing."""

from __future__ import annotations

from pathlib import Path

from ..diagnosis import auto_diagnose, diagnose
from ..model.terms import DEFAULT_MODEL, TERMS, parse_model
from .options import add_log_input, add_quiet, for_each_actuator


def add_parser(sub):
    p = sub.add_parser(
        "diagnose", help="find where the thermal model fails and which physical effect is missing",
        description="Fit the model (output error, first --split of the log), analyse its residual "
        "(autocorrelation; cross-correlation with effort, effort^2, |velocity|, current^2, ambient and the "
        "neighbours' temperatures; RMSE by phase), score every catalog effect the model lacks, refit the "
        "strong ones and recommend the one to add. Errors in K.",
    )
    add_log_input(p)
    p.add_argument("--model", default=",".join(DEFAULT_MODEL), metavar="TERMS",
                   help=f"model to diagnose (default {','.join(DEFAULT_MODEL)}); known terms: {', '.join(TERMS)}")
    p.add_argument("--split", type=float, default=0.7, help="fraction of the time span used to fit (default 0.7)")
    p.add_argument("--cv", type=int, default=None, metavar="K",
                   help="blocked cross-validation: K contiguous folds, each validated by free run from its "
                        "measured start, instead of the single split")
    p.add_argument("--auto", action="store_true",
                   help="add recommended effects one at a time while each helps, and draw the waterfall")
    p.add_argument("--refit", choices=("strong", "all"), default="strong",
                   help="refit only strong candidates (default) or all of them")
    p.add_argument("--json", action="store_true", help="print the diagnosis as one JSON object")
    p.add_argument("--plot", default=None, metavar="DIR", help="write the diagnosis plots into DIR")
    add_quiet(p)
    p.set_defaults(func=run)


def run(args) -> int:
    parse_model(args.model)

    def analyse(name, series):
        if args.auto:
            d, _ = auto_diagnose(series, args.model, split=args.split, quiet=args.quiet, cv=args.cv)
        else:
            d = diagnose(series, args.model, split=args.split, refit=args.refit, quiet=args.quiet, cv=args.cv)
        if args.plot:
            from ..diagnosis.plots import plot_diagnosis

            plot_diagnosis(d, Path(args.plot), name.replace("/", "_"))
        return d.to_json(), _describe(d)

    return for_each_actuator(args, analyse)


def _describe(d) -> str:
    b = d.base.validation
    lines = [f"{d.actuator}: model {','.join(d.model)}: validation RMSE {b['rmse_K']:.3f} K, "
             f"fit {b['fit_percent']:.1f} %"]
    for c in d.candidates:
        if c.rmse_K is None:
            lines.append(f"  {c.effect:18s} not refitted (score test p = {c.p_value:.2g})")
            continue
        name = c.effect + (f" for {c.replaces}" if c.replaces else "")
        lines.append(f"  {name:18s} RMSE {c.rmse_K:.3f} K  improvement {100 * c.improvement:5.1f} %  "
                     f"dBIC {c.delta_bic:9.1f}  identifiable {c.identifiable}")
        lines.append(f"      {c.evidence}")
    lines.append(f"  recommended: {d.recommended.effect if d.recommended else 'none'}")
    if d.auto:
        lines.append("  waterfall: " + "  ->  ".join(f"{s['rmse_K']:.3f} K" for s in d.auto))
    return "\n".join(lines)

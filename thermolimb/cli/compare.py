"""``thermolimb compare``: several models side by side on one log."""

from __future__ import annotations

from pathlib import Path

from ..util.atomic import file_stem
from ..workbench.compare import compare_models, rank_models
from .output import format_params
from .template import LogCommand, Run


class Compare(LogCommand):
    name = "compare"
    help = "compare several models on one log: held-out error, AIC/BIC, parameters, overlay"
    description = ("Fit each --model on the first --split of the "
                   "log (or by --cv K folds) and validate by free "
                   "run: validation RMSE (K), max error (K), fit %, "
                   "AIC and BIC on the training residual, parameters.")
    model_help = "a model to compare"
    many_models = True
    json_help = "print the comparison as one JSON object"
    plot_help = "write compare_<actuator>.png into DIR"

    def analyse(self, run: Run, name, series, scheme):
        results = compare_models(series, run.models, scheme, run.datasheet)
        fitted = [(r, ic) for r, ic in results if r is not None]
        if run.page is not None:
            from ..plotting.interactive import temperature_figure, thinning_note

            run.page.add(f"{name}: measured against each model",
                         temperature_figure([(",".join(r.model.terms), r) for r, _ in fitted], name),
                         "Each model's free run, dotted where fitted and "
                         "solid on held-out data (shaded); the panels "
                         "share the time axis." + thinning_note(fitted[0][0]))
        if run.args.plot:
            from ..plotting.fits import plot_comparison

            plot_comparison(fitted, name, Path(run.args.plot) / f"compare_{file_stem(name)}.png")
        lines = [f"{name}:", f"  {'model':40s} {'RMSE K':>8s} {'max K':>8s} "
                             f"{'fit %':>7s} {'AIC':>11s} {'BIC':>11s}"]
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


add_parser = Compare().add_parser

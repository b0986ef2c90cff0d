"""``thermolimb predict``: how long until each joint reaches a temperature, from a saved model."""

from __future__ import annotations

from pathlib import Path

from ..util.atomic import file_stem
from ..util.errors import UsageError
from .options import add_log_input, add_temperature, add_terms
from .output import say
from .reading import in_model_units, load_model_file, read_logs, runs_of, say_notes
from .template import Command, Outcome
from .types import SEED, TEMPERATURE_C, integer, number, output_dir


class Predict(Command):
    name = "predict"
    help = "forecast when each actuator reaches a temperature, with an interval, from a model file"
    description = ("Free-run the saved model from the LOG's first reading (or --start-C) under the LOG's "
                   "inputs, or under a plan held for --duration (--hold, no LOG), and say when the predicted "
                   "temperature first reaches --threshold, with an interval at --level that combines the "
                   "parameters' uncertainty and the model error seen on held-out data (docs/model-file.md). "
                   "Times in s, temperatures in degC.")

    def add_options(self, p):
        p.add_argument("model_file", metavar="MODEL.json", help="a model file written by fit or diagnose "
                       "with --save")
        add_log_input(p, required=False)
        add_terms(p)
        p.add_argument("--threshold", type=TEMPERATURE_C, default=None, metavar="C",
                       help="the temperature to reach (degC; default: the limit stored in the model file)")
        p.add_argument("--level", type=number(0.0, 1.0, low_open=True, high_open=True), default=0.9,
                       help="the interval's level (default 0.9)")
        add_temperature(p, "--start-C", "start from this temperature instead of the log's first reading "
                        "(required with --hold)")
        p.add_argument("--hold", default=None, metavar="EFFORT[,VELOCITY]",
                       help="a plan instead of a log: the effort (in the model's unit) and velocity held for "
                            "--duration")
        p.add_argument("--duration", type=number(0.0, 1e7, low_open=True, unit="s"), default=None,
                       metavar="S", help="with --hold: how long the plan is held (s)")
        p.add_argument("--ambient-C", dest="ambient_C", type=number(-60.0, 150.0, unit="degC"), default=None,
                       metavar="C",
                       help="with --hold: the ambient temperature (a model that does not read it "
                       "moves its offset with it beyond the one it was identified in)")
        p.add_argument("--draws", type=integer(0, 10000), default=64,
                       help="parameter draws for the interval (default 64; 0: model error only)")
        p.add_argument("--seed", type=SEED, default=0, help="seed of the parameter draws")
        p.add_argument("--json", action="store_true", help="print one JSON object per actuator (a list when "
                                                           "several)")
        p.add_argument("--plot", type=output_dir, default=None, metavar="DIR",
                       help="write predict_<actuator>.png (the band, the threshold, the readings) into DIR")

    def check(self, args):
        if args.hold is None and not args.logs:
            raise UsageError("predict needs a LOG to run the model over, or a plan: --hold EFFORT[,VELOCITY] "
                             "--duration S --start-C C")
        if args.hold is not None and args.logs:
            raise UsageError("--hold is a plan instead of a log; give one or the other")
        if (args.duration is not None or args.ambient_C is not None) and args.hold is None:
            raise UsageError(
                "--duration and --ambient-C describe a --hold plan; add --hold EFFORT[,VELOCITY]"
            )
        if args.hold is not None:
            _hold(args.hold)
            if args.duration is None or args.start_C is None:
                raise UsageError("--hold needs --duration S and --start-C C (a plan has no first reading)")

    def work(self, args) -> Outcome:
        results = _forecasts(args, load_model_file(args))
        if args.plot:
            from ..plotting.forecast import plot_forecast

            for f in results:
                plot_forecast(f, Path(args.plot) / f"predict_{file_stem(f.actuator)}.png")
        records = [f.to_json() for f in results]
        return Outcome(records[0] if len(records) == 1 else records, "\n".join(_text(f) for f in results))


add_parser = Predict().add_parser


def _forecasts(args, models) -> list:
    from ..forecast import forecast, hold_signals

    results = []
    if args.hold is not None:
        effort, velocity = _hold(args.hold)
        names = [args.actuator] if args.actuator else list(models.actuators)
        for name in names:
            saved = models[name]
            signals = hold_signals(args.duration, effort, velocity, args.ambient_C, saved.model.columns)
            results.append(forecast(saved, signals, args.start_C, _threshold(args, saved), args.level,
                                    args.draws, args.seed))
        return results
    logs = read_logs(args.logs, args)
    names = [args.actuator] if args.actuator else _modelled(models, list(logs[0].actuators), args)
    say_notes(logs, names)
    for name in names:
        saved = _model_for(models, name, logs, args)
        for series in runs_of(logs, name):
            series = in_model_units(saved, series, args.model_file)
            start = series.temperature_C[0] if args.start_C is None else args.start_C
            rate = series.rate_K_per_s() if args.start_C is None else 0.0
            results.append(forecast(saved, series.signals, start, _threshold(args, saved),
                                    args.level, args.draws, args.seed, rate, series.temperature_C))
    return results


def _text(f) -> str:
    lines = [f.sentence(), *(f"  {note}" for note in f.notes)]
    if f.measured_crossing_s is not None:
        lines.append(f"  the log's readings reach it at {f.measured_crossing_s:.0f} s: "
                     f"{'inside' if f.covers_measured else 'outside'} the interval")
    if f.measured_error_K is not None:
        lines.append("  over the log, the forecast against its readings: RMSE "
                     f"{f.measured_error_K[0]:.3g} K, largest {f.measured_error_K[1]:.3g} K")
    if f.model_error_K == 0.0:
        lines.append("  the model file holds no held-out residual: the interval covers the parameters' "
                     "uncertainty only")
    return "\n".join(lines)


def _hold(text: str) -> tuple[float, float | None]:
    import math

    parts = text.split(",")
    try:
        values = [float(v) for v in parts]
    except ValueError:
        values = []
    if len(parts) not in (1, 2) or len(values) != len(parts) or not all(math.isfinite(v) for v in values):
        raise UsageError(f"--hold expects EFFORT or EFFORT,VELOCITY (finite numbers), got {text!r}")
    return values[0], values[1] if len(values) == 2 else None


def _threshold(args, saved) -> float:
    if args.threshold is not None:
        return args.threshold
    if saved.limit_C is None:
        raise UsageError(f"the model of {saved.actuator} stores no limit; give --threshold C")
    return saved.limit_C


def _modelled(models, names: list[str], args) -> list[str]:
    """The log's actuators the model file has a model of (each other one said), or all of them where it has
    none (the file's only model then answers for the log's only actuator, or the read is refused by name)."""
    shared = [n for n in names if n in models.actuators]
    if shared and len(shared) < len(names):
        left = ", ".join(n for n in names if n not in shared)
        them = "them" if "," in left else "it"
        say(f"the log's {left} not predicted: {args.model_file} has no model of {them}")
    return shared or names


def _model_for(models, name: str, logs, args):
    if name in models.actuators:
        return models[name]
    if len(models.actuators) == 1 and len(logs[0].actuators) == 1:
        only = next(iter(models.actuators))
        say(f"the log's actuator {name!r} is predicted with the model file's only model, {only!r}")
        return models[only]
    raise UsageError(f"{args.model_file} has no model of actuator {name!r} (it has "
                     f"{', '.join(models.actuators)}); choose one with --actuator")

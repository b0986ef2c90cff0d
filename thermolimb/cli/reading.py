"""Reading the logs a command names, with the options it was given: terms files first, then each log
(one actuator of a large table in pieces, the neighbours only when a model may use them), and its notes."""

from __future__ import annotations

import argparse
import hashlib

import numpy as np

from ..logs import ActuatorSeries, ThermalLog, parse_mapping, read_log
from ..logs.formats import asked_for
from ..util.errors import LogError, UsageError
from .options import SEPARATORS
from .output import say


def load_terms(args) -> None:
    from ..model.generated import load_term_file

    for path in getattr(args, "terms", None) or ():
        load_term_file(path)


def load_model_file(args):
    """The command's terms files, then its model file (checked as a log is), what loading it said said."""
    from ..model.saved import ModelFile

    load_terms(args)
    models = ModelFile.load(args.model_file)
    for note in models.notes:
        say(note)
    return models


def read_options(args, path) -> dict:
    """The keyword arguments of :func:`read_log` that the command line's options give for ``path``."""
    mapping = parse_mapping(args.map)
    return {"mapping": mapping, "velocity_unit": args.velocity_unit, "effort_unit": args.effort_unit,
            "sep": SEPARATORS[args.sep] if args.sep else None, "decimal": args.decimal,
            "drop_incomplete": args.drop_incomplete, "columns": getattr(args, "columns", None),
            # one actuator: a bag's joint, a wide table's name, or a long table's rows (and its neighbours')
            **asked_for(path, args.actuator, mapping), "neighbours": reads_neighbours(args)}


def reads_neighbours(args) -> bool:
    """Whether the command needs the neighbours' temperatures: a diagnosis may add their coupling; a fit or a
    comparison only when one of its models has it."""
    from ..model.terms import DEFAULT_MODEL, TERMS, parse_model

    if getattr(args, "discovers", True) or not hasattr(args, "model"):
        return True
    models = args.model if isinstance(args.model, list) else [args.model or DEFAULT_MODEL]
    return any("neighbors" in TERMS[name].columns for spec in models for name in parse_model(spec))


def read_logs(paths, args) -> list[ThermalLog]:
    """Every log of ``paths``, read alike."""
    return [read_log(path, **read_options(args, path)) for path in paths]


def read_held(args) -> list[ThermalLog]:
    """The ``--validate-on`` logs, read as the others but by ``--validate-map`` where given (what it refuses
    is said of it)."""
    if not args.validate_on:
        return []
    if args.validate_map is None:
        return read_logs(args.validate_on, args)
    try:
        return read_logs(args.validate_on, argparse.Namespace(**{**vars(args), "map": args.validate_map}))
    except (LogError, UsageError) as exc:
        raise type(exc)(str(exc).replace("--map", "--validate-map")) from exc


def runs_of(logs: list[ThermalLog], name: str) -> list[ActuatorSeries]:
    """Actuator ``name``'s runs over every log, in order."""
    return [run for log in logs for run in log.runs(name)]


def distinct_runs(logs: list[ThermalLog], held: list[ThermalLog], name: str) -> tuple[list, list]:
    """Actuator ``name``'s runs over ``logs`` and over ``held`` (``--validate-on``), as :func:`runs_of` gives
    them; a run given twice among them (one log named twice, or a copy under another name) is refused: held
    out beside itself it would be judged on the readings it was fitted on."""
    # a run's readings (time, temperature, effort), digested: the log it came from
    seen: dict[bytes, str] = {}
    groups: tuple[list, list] = ([], [])
    for group, some in zip(groups, (logs, held)):
        for log in some:
            for run in log.runs(name):
                digest = hashlib.sha256()
                for values in (run.time_s, run.temperature_C, run.signals.effort):
                    digest.update(np.ascontiguousarray(values, dtype=float).tobytes())
                key = digest.digest()
                source = seen.get(key)
                if source is not None:
                    what = (f"{source} is given twice" if source == log.source else
                            f"{log.source} holds the same readings of {name!r} as {source}")
                    raise UsageError(f"{what}: a run fitted on and held out beside itself is judged on the "
                                     f"readings it was fitted on; give each run once")
                seen[key] = log.source
                group.append(run)
    return groups


def say_notes(logs: list[ThermalLog], names) -> None:
    """What reading changed in each log, and the runs the actuators' logging pauses cut it into."""
    for log in logs:
        for note in log.notes:
            say(note)
        for name in names:
            if name in log.actuators:
                gap = log.describe_gaps(name)
                if gap:
                    say(gap)


def in_model_units(saved, series, source):
    """The run with its effort in the unit the model was fitted on (converted where both are units of one
    kind, mA and A, and said; refused otherwise), its velocity in the model's."""
    from dataclasses import replace

    from ..model.parameter_units import effort_factor

    unit, given = saved.channel_units.get("effort", ""), series.units.get("effort", "")
    factor = effort_factor(unit, given, f"the model in {source}")
    if factor != 1.0:
        say(f"{series.run or series.actuator}: the log's effort in {given} read in {unit}, the model's unit")
        series = replace(series, signals=replace(series.signals, effort=series.signals.effort * factor))
    for channel in ("velocity",):
        model_unit, log_unit = saved.channel_units.get(channel), series.units.get(channel)
        if log_unit and model_unit and log_unit != model_unit:
            raise UsageError(f"the model in {source} was fitted on {channel} in {model_unit}; this log gives "
                             f"{channel} in {log_unit}; convert it (--{channel}-unit) or refit")
    missing = [c for c in saved.model.columns if not series.signals.has(c)]
    if missing:
        raise UsageError(f"the model of {saved.actuator} reads the log column {missing[0]!r}, which this log "
                         f"does not have")
    return series

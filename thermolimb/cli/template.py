"""One template for every command: options, checks before anything is read, the work (reading included),
printing, and the files written (:class:`Command`).

Every command subclasses :class:`Command` and says only what it adds: its options (``--quiet`` comes last,
from the template), its checks, and its work, which returns an :class:`Outcome` -- the JSON record ``--json``
prints, the text printed otherwise, the files it wrote; the template prints one or the other and says each
file written (``wrote PATH``, or ``replaced PATH`` for one that was there before).

:class:`LogCommand` (``fit``, ``compare``, ``diagnose``) is the template for commands that read logs and
analyse each actuator: their shared options (logs and how to read them, terms files, models, validation,
``--json``/``--plot``/``--html``, ``--fleet`` where it has one), the checks made before any log is read
(``--datasheet`` against the models, once), reading the logs and saying what reading changed, and one
analysis per actuator (:meth:`LogCommand.analyse`).
"""

from __future__ import annotations

import contextlib
import sys
from dataclasses import dataclass, field
from pathlib import Path

from ..logs import LogError
from ..logs.validate import SET_ASIDE
from ..util.errors import TermError, ThermolimbError, UsageError
from ..workbench.excitation import refuse_unfittable
from ..workbench.validation import Scheme
from .options import (
    add_fleet,
    add_log_input,
    add_models,
    add_outputs,
    add_quiet,
    add_save,
    add_terms,
    add_validation,
    scheme_of,
)
from .output import existing, files_in, html_page, print_json, say, say_written
from .reading import distinct_runs, load_terms, read_held, read_logs, say_notes


@dataclass(frozen=True)
class Outcome:
    """What a command's work hands the template: ``record`` (printed with ``--json``), ``text`` (printed
    otherwise; empty: nothing), the files it wrote beside its plots' folder (``written``), the exit status,
    and where the record or text goes (``stream``: standard output unless the command's product goes there).
    """

    record: object = None
    text: str = ""
    written: tuple = ()
    status: int = 0
    stream: object = None


class Command:
    """A subcommand: fill in ``name``, ``help`` and ``description`` (and ``parser_options``: argparse's
    ``formatter_class``, ``epilog``), and define :meth:`add_options` and :meth:`work`; :meth:`check` and
    :meth:`outputs` where the command has checks or writes files."""

    name = ""
    help = ""
    description = ""
    parser_options: dict = {}
    plots = "plot"  # the option naming the folder the command writes plots into: its new files are said

    def add_parser(self, sub):
        p = sub.add_parser(self.name, help=self.help, description=self.description, **self.parser_options)
        self.add_options(p)
        add_quiet(p)
        p.set_defaults(func=self.run, discovers=False)
        return p

    def add_options(self, p) -> None:
        """The command's options."""

    def check(self, args) -> None:
        """The command's checks of its options, before anything is read (raise :class:`UsageError`)."""

    def outputs(self, args) -> tuple:
        """The files this run will write (``None`` for one it will not): one already there is said as
        replaced."""
        return ()

    def work(self, args) -> Outcome:
        """Reading, and what the command is for."""
        raise NotImplementedError  # abstract: every command defines it

    def run(self, args) -> int:
        self.check(args)
        folder = getattr(args, self.plots, None) if self.plots else None
        before, existed = files_in(folder), existing(*self.outputs(args))
        outcome = self.work(args)
        stream = outcome.stream or sys.stdout
        if getattr(args, "json", False) and outcome.record is not None:
            print_json(outcome.record, stream)
        elif outcome.text:
            print(outcome.text, file=stream)
        say_written(before, folder, outcome.written, existed)
        return outcome.status


@dataclass
class Run:
    """One invocation of a command: its arguments and what the template made of them before reading."""

    args: object
    models: list[tuple[str, ...]]
    scheme: object
    datasheet: dict[str, float]
    page: object = None  # the --html page the analyses fill, or None
    kept: list = field(default_factory=list)  # what a command keeps across actuators for its finish()
    final: dict = field(default_factory=dict)  # each actuator's final fit report, for --save


class LogCommand(Command):
    """A subcommand that reads logs and analyses each actuator; subclasses fill in the class attributes and
    :meth:`analyse`, and may add :meth:`add_options`, :meth:`check` and :meth:`finish`."""

    name = ""
    help = ""
    description = ""
    model_help = "model"
    many_models = False  # --model repeated (compare)
    fleet = False  # --fleet: every actuator and run of many logs on its own
    # whether an analysis may add the neighbours' coupling (then their temperatures are read)
    discovers = False
    saves = False  # --save MODEL.json: the analysis's final model of each actuator (run.final)
    save_help = "write the fitted model of each actuator to a model file (JSON; docs/model-file.md)"
    json_help = "print one JSON object per actuator (a list when several actuators)"
    plot_help = "write plots into DIR"

    def add_parser(self, sub):
        p = sub.add_parser(self.name, help=self.help, description=self.description)
        add_log_input(p)
        add_terms(p)
        add_models(p, self.model_help, repeated=self.many_models)
        self.add_options(p)
        add_validation(p)
        add_outputs(p, self.json_help, self.plot_help)
        if self.saves:
            add_save(p, self.save_help)
        if self.fleet:
            add_fleet(p)
        add_quiet(p)
        p.set_defaults(func=self.run, discovers=self.discovers)
        return p

    def add_options(self, p) -> None:
        """The command's own options."""

    def check(self, args) -> None:
        """The command's own checks of its options, before any log is read (raise :class:`UsageError`)."""

    def analyse(self, run: Run, name: str, series: list, scheme) -> tuple[dict, str]:
        """One actuator's analysis: its JSON record and its text."""
        raise NotImplementedError  # abstract: every log command defines it

    def finish(self, run: Run) -> None:
        """After every actuator (writes what the command keeps across them)."""

    def run(self, args) -> int:
        load_terms(args)
        from ..model.terms import DEFAULT_MODEL, parse_model

        given = args.model if isinstance(args.model, list) else [args.model]
        models = [parse_model(m) for m in given] if args.model is not None else [tuple(DEFAULT_MODEL)]
        datasheet = _checked_datasheet(args.datasheet, models)
        self.check(args)
        if getattr(args, "save", None) and getattr(args, "fleet", False):
            raise UsageError("--save writes the model of one command's "
                             "logs, not of a --fleet; fit a run with --save")
        if self.fleet and not args.fleet:
            given = [flag for flag, value in (("--table", args.table), ("--workers", args.workers),
                                              ("--address", args.address)) if value is not None]
            given += ["--backend"] if args.backend != "process" else []
            if given:
                raise UsageError(f"{given[0]} works with --fleet (many logs, "
                                 "each actuator and run on its own); add "
                                 f"--fleet or leave {given[0]} out")
        if getattr(args, "limit_C", None) is not None and not getattr(args, "save", None):
            raise UsageError("--limit-C is stored in the model file; add --save MODEL.json")
        if self.fleet and args.fleet:
            from .fleet import run_fleet

            return run_fleet(args, diagnose=self.name == "diagnose", datasheet=datasheet)
        run = Run(args, models, scheme_of(args), datasheet, html_page(args, f"thermolimb {self.name}"))
        status = self._each_actuator(run)
        self.finish(run)
        return status

    def _each_actuator(self, run: Run) -> int:
        """:meth:`analyse` for the chosen actuator or every one: what reading changed on standard error, each
        text (or with ``--json`` one record, a list when several actuators), the page, the files written."""
        args = run.args
        logs = read_logs(args.logs, args)
        held = read_held(args)
        names = [args.actuator] if args.actuator else list(logs[0].actuators)
        say_notes(logs + held, names)
        before = files_in(args.plot)
        existed = existing(args.html, getattr(args, "save", None))
        records, failed = [], []
        for name in names:
            missing = [log for log in logs + held if name not in log.actuators]
            if missing:
                named = [log for log in logs + held if log.actuators == (Path(log.source).stem,)]
                # each file's one actuator named after it
                if len(named) == len(logs + held) and not args.actuator:
                    raise UsageError(
                        f"{missing[0].source}: its actuator is "
                        f"named {missing[0].actuators[0]!r} after "
                        f"the file, as {logs[0].source}'s is {name!r} ("
                        f"{'the map names no actuator' if args.map else 'the file has no actuator column'}"
                        f"); to read the files as runs of one actuator, name it: --actuator NAME"
                    )
                aside = next((n for n in missing[0].notes if f"actuator {name!r}" in n and SET_ASIDE in n),
                             None)
                if aside is not None:
                    raise LogError(aside.replace(f"; {SET_ASIDE}", ""))
                raise UsageError(f"{missing[0].source}: no actuator {name!r}; the log has "
                                 f"{', '.join(missing[0].actuators)}")
            try:
                # with --json, standard output carries the JSON alone: whatever a user's term prints goes to
                # stderr
                with contextlib.redirect_stdout(sys.stderr) if args.json else contextlib.nullcontext():
                    runs, held_runs = distinct_runs(logs, held, name)
                    refuse_unfittable(runs + held_runs, name)
                    scheme = Scheme.on_runs(held_runs) if held_runs else run.scheme
                    record, text = self.analyse(run, name, runs, scheme)
            except ThermolimbError as exc:
                # every actuator of the log: one the log cannot tell about is said, and the others go on
                if args.actuator or len(names) == 1 or isinstance(exc, (UsageError, TermError)):
                    raise
                failed.append(name)
                record, text = {"actuator": name, "error": str(exc)}, f"{name}: not analysed: {exc}"
            records.append(record)
            if not args.json:
                print(text)
        if len(failed) == len(names):
            raise ThermolimbError(records[0]["error"])
        if failed:
            say(f"{len(failed)} of {len(names)} actuators could "
                f"not be analysed ({', '.join(failed)}); the others "
                f"were")
        if args.json:
            print_json(records[0] if len(records) == 1 else records)
        if run.page is not None:
            run.page.write(args.html)
        saved = [save_models(args, run.final)] if getattr(args, "save", None) else []
        say_written(before, args.plot, ([args.html] if run.page is not None else []) + saved, existed)
        return 1 if failed else 0


def save_models(args, final: dict):
    """Write ``--save``: every actuator's final report as a model file (with ``--limit-C``, its limit)."""
    from ..model.saved import ModelFile
    from ..workbench.saving import saved_from_report

    models = {name: saved_from_report(report, args.logs, args.limit_C) for name, report in final.items()}
    return ModelFile(models).save(args.save)


def _checked_datasheet(values: dict[str, float], models) -> dict[str, float]:
    """``--datasheet``, checked against the models' parameters before any log is read (the one place)."""
    from ..workbench.submodel import check_datasheet

    try:
        check_datasheet(values, *models)
    except LogError as exc:
        raise UsageError(str(exc)) from None
    return dict(values)

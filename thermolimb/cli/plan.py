"""``thermolimb plan``: the test that sizes what a log could not, within the actuator's limits."""

from __future__ import annotations

from pathlib import Path

from ..util.errors import UsageError
from .options import add_temperature, add_terms
from .reading import load_model_file
from .template import Command, Outcome
from .types import SEED, names_list, number, output_dir, output_file


class Plan(Command):
    name = "plan"
    help = "design the test that sizes a parameter a log could not, within the actuator's limits"
    description = ("From a model file and the parameters a log left unsized (--identify), write a test of "
                    "piecewise-constant holds (--out plan.csv: time, actuator, effort[, velocity]) that "
                    "maximises what its fit will tell about them (the Fisher information of the free run) "
                    "while the winding stays --margin-K under --limit-C at the upper end of the model's 90 % "
                    "forecast interval, within --max-effort and --duration; say the standard errors it "
                    "promises. Run it on the plant with thermolimb simulate --profile plan.csv, or on the "
                    "robot with its own controller and protection (docs/workbench.md). Times in s, "
                    "temperatures in degC, effort in the model's unit.")

    def add_options(self, p):
        p.add_argument("model_file", metavar="MODEL.json",
                       help="a model file written by fit or diagnose with --save")
        add_terms(p)
        question = p.add_mutually_exclusive_group(required=True)
        question.add_argument("--identify", type=names_list, metavar="PARAM,...", help="the model's "
                              "parameters to size (e.g. frame_tau_s, alpha_per_K, sensor_tau_s)")
        question.add_argument("--separate", type=names_list, metavar="A,B", help="two effects the log could "
                              "not tell apart, one in the model and one not (e.g. " "joule,winding_tempco): "
                              "the test that tells the model from its rival")
        question.add_argument("--questions", type=Path, metavar="DIAGNOSIS.json",
                              help="the open questions of a diagnosis (diagnose --save MODEL.json --json > "
                                   "DIAGNOSIS.json): its confounded pair if it has one, else its unsized "
                                   "parameters")
        p.add_argument("--actuator", default=None, metavar="NAME",
                       help="the model file's actuator (default: its one)")
        add_temperature(p, "--limit-C", "the winding's limit (default: the model file's)")
        p.add_argument("--margin-K", dest="margin_K", type=number(0.0, 200.0, unit="K"), default=5.0,
                       metavar="K",
                       help="kept between the forecast band's upper end and the limit (default 5 K)")
        p.add_argument("--max-effort", dest="max_effort", type=number(0.0, 1e9, low_open=True), required=True,
                       metavar="E", help="the largest effort the test may hold, in the model's effort unit")
        p.add_argument("--max-velocity", dest="max_velocity", type=number(0.0, 1e4), default=0.0,
                       metavar="RAD_S",
                       help="the largest velocity (rad/s), for a model that reads it (default 0: no motion)")
        seconds = number(0.0, 1e7, low_open=True, unit="s")
        p.add_argument("--duration", type=seconds, required=True, metavar="S", help="the test's length (s)")
        p.add_argument("--dt", type=number(0.0, 3600.0, low_open=True, unit="s"), default=1.0, metavar="S",
                       help="the sample period of the plan and of the readings its fit compares (default 1 "
                       "s)")
        p.add_argument("--min-hold", dest="min_hold", type=seconds, default=None, metavar="S",
                       help="the shortest hold (default ten samples)")
        add_temperature(p, "--start-C", "where the winding starts (default --ambient-C)")
        p.add_argument("--ambient-C", dest="ambient_C", type=number(-60.0, 150.0, unit="degC"), default=25.0,
                       metavar="C", help="the air the test runs in (default 25)")
        p.add_argument("--noise-K", dest="noise_K", type=number(0.0, 100.0, low_open=True, unit="K"),
                       default=None, metavar="K",
                       help="the readings' noise (default: the model's held-out RMSE; the sensor's "
                       "floor diagnose reports is the better value)")
        p.add_argument("--seed", type=SEED, default=0, help="seed of the search's starts")
        p.add_argument("--out", type=output_file, required=True, metavar="PLAN.csv",
                       help="the plan, as set-points")
        p.add_argument("--plot", type=output_dir, default=None, metavar="DIR",
                       help="write plan_<actuator>.png (the profile, the predicted winding, its band and the "
                            "limit)")
        p.add_argument("--json", action="store_true", help="print the plan's promise as JSON")

    def outputs(self, args):
        return (args.out,)

    def work(self, args) -> Outcome:
        from ..experiment import Limits, design
        from ..util.atomic import atomic_path

        models = load_model_file(args)
        names = list(models.actuators)
        if args.actuator is None and len(names) > 1:
            raise UsageError(f"the model file holds {', '.join(names)}: name one with --actuator")
        name = args.actuator or names[0]
        if name not in models.actuators:
            raise UsageError(
                f"--actuator {name}: the model file has no such actuator; it has {', '.join(names)}"
            )
        saved = models[name]
        asked_from = None
        if args.questions is not None:
            args.separate, args.identify, floor_K = _asked(args.questions, name, saved)
            if args.noise_K is None and floor_K:
                args.noise_K = floor_K  # the sensor's floor the diagnosis measured on the log
            question = (f"--separate {','.join(args.separate)}" if args.separate
                        else f"--identify {','.join(args.identify)}")
            asked_from = f"  answers: {question}, the question {args.questions} leaves open"
        limit = args.limit_C if args.limit_C is not None else saved.limit_C
        if limit is None:
            raise UsageError(f"the model of {name} stores no limit; give --limit-C C")
        start = args.ambient_C if args.start_C is None else args.start_C
        limits = Limits(limit_C=limit, max_effort=args.max_effort, duration_s=args.duration, start_C=start,
                        dt_s=args.dt, margin_K=args.margin_K, max_velocity=args.max_velocity,
                        min_hold_s=args.min_hold, ambient_C=args.ambient_C)
        if args.separate is not None:
            from ..separation import separate

            if len(args.separate) != 2:
                raise UsageError(f"--separate takes two effects, A,B; got {len(args.separate)}")
            plan = separate(saved, args.separate, limits, noise_K=args.noise_K, seed=args.seed)
        else:
            plan = design(saved, args.identify, limits, noise_K=args.noise_K, seed=args.seed)
        with atomic_path(args.out) as tmp:
            plan.table().to_csv(tmp, index=False)
        if args.plot:
            from ..plotting.plan import plot_plan

            plot_plan(plan, Path(args.plot))
        record = {**plan.to_json(), **({"questions_from": str(args.questions)} if asked_from else {})}
        text = plan.lines() + ([asked_from] if asked_from else [])
        text.append(f"  run it on the plant: thermolimb simulate --profile {args.out} --actuators "
                    f"{name}:MODEL " f"--dt {args.dt:g} --out test.csv")
        return Outcome(record, "\n".join(text), (args.out,))


add_parser = Plan().add_parser


def _asked(path: Path, name: str, saved) -> tuple[list[str] | None, list[str] | None, float | None]:
    """``(separate, identify, floor_K)`` from a diagnosis's JSON record (one actuator's, or a list of
    them): the question it leaves open for actuator ``name``, whose model must be the model file's, and the
    sensor's floor it measured (``None``: not measured)."""
    import json

    from ..workbench.diagnosis.questions import Questions

    try:
        record = json.loads(path.read_text())
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise UsageError(f"--questions {path}: not a diagnosis's JSON record ({exc}); expected the output of "
                         f"thermolimb diagnose ... --json") from None
    records = record if isinstance(record, list) else [record]
    found = [r for r in records if isinstance(r, dict) and r.get("actuator") == name]
    if not found or not isinstance(found[0].get("open_questions"), dict):
        raise UsageError(f"--questions {path}: no open questions of actuator {name}; expected the output of "
                         f"thermolimb diagnose ... --actuator {name} --json")
    try:
        asked = Questions.from_json(found[0]["open_questions"])
    except (KeyError, TypeError, IndexError) as exc:
        raise UsageError(f"--questions {path}: its open questions are not readable ({exc!r})") from None
    if set(asked.model) != set(saved.model.terms):
        raise UsageError(f"--questions {path}: the diagnosis's model is {','.join(asked.model)}, the model "
                         f"file's {','.join(saved.model.terms)}; save the model the diagnosis ends with "
                         f"(--save)")
    floor = found[0].get("floor") or {}
    floor_K = floor.get("floor_K") if isinstance(floor.get("floor_K"), (int, float)) else None
    if asked.separate is not None:
        return list(asked.separate), None, floor_K
    if asked.identify:
        return None, list(asked.identify), floor_K
    raise UsageError(f"--questions {path}: the diagnosis of {name} leaves no question a test can answer (no "
                     f"parameter unsized, no effect confounded with one of the model's)")

"""``thermolimb simulate``: write a log from the thermal plant."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from ..logs import write_pieces
from ..logs.formats import written_as
from ..plant import (
    ACTUATOR_SPECS,
    NETWORKS,
    PLANT_EFFECTS,
    PROFILES,
    PlantEffects,
    simulate_profile,
    simulate_profile_in_pieces,
)
from ..plant.cases import CASE_NAMES, CASE_SPECS
from ..util.atomic import is_stream
from ..util.errors import UsageError
from .template import Command, Outcome
from .types import AMBIENT_C, SEED, number, output_file

MAX_ROWS = 30_000_000  # rows written at most (the profile's inputs, 16 bytes a row, are held whole)
DEFAULT_ACTUATORS = ",".join(f"{name}:{spec.model}" for name, spec in zip(CASE_NAMES, CASE_SPECS))


class Simulate(Command):
    name = "simulate"
    help = "write a log from the thermal plant driven by a built-in profile"
    description = ("Drive the thermal plant with a built-in effort/velocity profile and write a canonical "
        "log (time s, actuator, effort N m, temperature degC "
        "measured, velocity rad/s, current A, ambient degC).")

    def add_options(self, p):
        p.add_argument("--profile", default="squat", type=profile_name, metavar="NAME|PLAN.csv",
                       help="squat: Jorgensen et al.'s Fig. 5 squat every "
                       "4.5 min; single_leg: balancing on one leg; "
                       "walking: walking bouts and rests; random: random holds and motions (default squat); "
                       "or a plan's file (thermolimb plan --out), its set-points held from one to the next "
                       "for as long as it lasts (--duration is then the plan's)")
        p.add_argument("--duration", type=number(0.0, 1e8, low_open=True, unit="s"), default=3600.0,
                       help="simulated time in s (default 3600)")
        p.add_argument("--dt", type=number(0.0, 3600.0, low_open=True, unit="s"), default=0.1,
                       help="control and logging interval in s (default 0.1)")
        p.add_argument("--actuators", default=DEFAULT_ACTUATORS, metavar="NAME:MODEL,...",
                       help="actuators and their models "
                            f"({', '.join(ACTUATOR_SPECS)}); default {DEFAULT_ACTUATORS}")
        p.add_argument("--network", default="x8", choices=sorted(NETWORKS), help="thermal network of every "
                       "actuator (default x8: winding/housing/body, HEBI numbers)")
        p.add_argument("--effects", default="sensor_noise,quantisation", metavar="NAME,...",
                       help=f"plant effects to switch on, or 'none' (default sensor_noise,quantisation); "
                            f"known: {', '.join(PLANT_EFFECTS)}")
        p.add_argument("--load-scale", type=number(0.0, 100.0), default=1.0,
                       help="multiply every effort (a heavier payload), before the effort limits (default 1)")
        p.add_argument("--ambient", type=AMBIENT_C, default=25.0,
                       help="ambient temperature at t = 0 in degC, -60 to 150 (default 25)")
        p.add_argument("--drivers", action="store_true", help="also log each driver board as "
                       "'<actuator>/driver'")
        p.add_argument("--housing-sensor", action="store_true",
                       help="log a second thermistor on each actuator's housing (column 'housing', degC)")
        p.add_argument("--seed", type=SEED, default=0, help="seed of the profile and the sensor noise "
                       "(default 0)")
        p.add_argument("--out", type=output_file, required=True, help="log file to write: .csv, "
                                                                      ".parquet, or .mcap (a ROS 2 MCAP "
                                                                      "file that opens in Foxglove)")
        p.add_argument("--json", action="store_true", help="print a summary record")

    plots = None

    def work(self, args) -> Outcome:
        names, specs = parse_actuators(args.actuators)
        if args.profile not in PROFILES:  # a plan lasts as long as it does
            from ..plant.profiles import from_table

            args.duration = float(from_table(args.profile, args.dt, names, specs).time_s[-1])
        samples = args.duration / args.dt
        if samples * len(names) > MAX_ROWS:
            raise UsageError(
                f"--duration {args.duration:g} s at --dt {args.dt:g} s is {samples:.3g} samples of "
                f"{len(names)} actuators; at most {MAX_ROWS:,} rows are written (a longer --dt or a "
                "shorter --duration)"
            )
        written = written_as(args.out)  # an unknown format is one sentence, before the plant runs
        effects = PlantEffects.from_names(args.effects)
        options = dict(seed=args.seed, ambient_C=args.ambient, network=NETWORKS[args.network],
                       include_drivers=args.drivers, housing_sensor=args.housing_sensor, quiet=args.quiet,
                       load_scale=args.load_scale)
        seen = _Seen()
        if written == "mcap":  # a bag's messages interleave every channel: written whole
            run = next(
                seen.each(
                    [simulate_profile(args.profile, args.duration, args.dt, names, specs, effects, **options)]
                )
            )
            path = run.log.write(args.out)
        else:  # a table is written a piece at a time, so memory does not grow with the duration
            pieces = simulate_profile_in_pieces(args.profile, args.duration, args.dt, names, specs, effects,
                                                **options)
            path = write_pieces((run.log for run in seen.each(pieces)), args.out)
        record = {
            "out": str(path), "profile": args.profile, "duration_s": args.duration, "dt_s": args.dt,
            "actuators": list(seen.channels), "network": args.network, "effects": list(effects.names),
            "seed": args.seed, "max_true_winding_C": dict(zip(names, seen.hottest_C)),
        }
        said = sys.stderr if is_stream(path) else sys.stdout  # the log itself may be going to standard output
        return Outcome(record, f"wrote {path}: {seen.samples} samples x {len(seen.channels)} channels; "
                               f"hottest winding {max(seen.hottest_C):.1f} degC", stream=said)


add_parser = Simulate().add_parser


def profile_name(text: str) -> str:
    """A built-in profile's name, or an existing plan file."""
    if text in PROFILES:
        return text
    if text.lower().endswith((".csv", ".parquet")):
        if not Path(text).is_file():
            raise argparse.ArgumentTypeError(f"no plan file {text!r}")
        return text
    raise argparse.ArgumentTypeError(f"expected one of {', '.join(sorted(PROFILES))}, or a plan's .csv, got "
                                     f"{text!r}")


def parse_actuators(text: str):
    names, specs = [], []
    for item in text.split(","):
        name, _, model = item.strip().partition(":")
        if not name or model not in ACTUATOR_SPECS:
            raise UsageError(f"--actuators item {item!r} must be NAME:MODEL "
                             f"with MODEL one of {', '.join(ACTUATOR_SPECS)}")
        if name in names:
            raise UsageError(f"--actuators names {name!r} twice; give each actuator its own name")
        names.append(name)
        specs.append(ACTUATOR_SPECS[model])
    return names, specs

class _Seen:
    """What the simulated pieces held, counted as they pass: samples, channels, each winding's hottest."""

    def __init__(self):
        self.samples, self.channels, self.hottest_C = 0, (), None

    def each(self, pieces):
        for run in pieces:
            self.samples += len(run.time_s)
            self.channels = run.log.actuators
            hottest = run.true_winding_C.max(axis=0)
            self.hottest_C = hottest if self.hottest_C is None else np.maximum(self.hottest_C, hottest)
            yield run

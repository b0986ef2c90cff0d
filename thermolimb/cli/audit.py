"""``thermolimb audit``: will a policy overheat a joint, which one, and when -- in any Gymnasium
environment."""

from __future__ import annotations

import json

from ..util.errors import UsageError
from .options import add_temperature, add_terms
from .output import say
from .template import Command, Outcome
from .types import SEED, number, output_dir

PLANTS = {"x8-9": "X8_9", "x8-16": "X8_16"}


class Audit(Command):
    name = "audit"
    help = ("run a policy in an environment whose joints "
                      "heat up: peak temperatures, time to the limit")
    description = ("Run a policy for --duration seconds of simulated "
                    "time in a Gymnasium environment (a MuJoCo "
                    "one such as Ant-v5 or Humanoid-v5, or one of this suite's robots) wrapped with "
                    "thermolimb.envs.ThermalWrapper: each joint heated "
                    "from the torque it is given, by the models in "
                    "--models or by the suite's plant with datasheet "
                    "actuators (--plant). Reports per joint the peak "
                    "temperature, when it reached its limit (or not "
                    "within the run) and which joint limits the run; "
                    "the heat carries over episodes, each reset counted (docs/travel.md).")

    def add_options(self, p):
        p.add_argument("--env", required=True, metavar="ID", help="a Gymnasium environment "
                                                                  "id (Ant-v5, Humanoid-v5, "
                                                                  "thermolimb/HexapodLoadCarry-v0, ...)")
        p.add_argument("--policy", default="zero", metavar="zero|random|MODULE:CALLABLE",
                       help="zero actions, seeded random ones, or a function "
                            "(env, observation) -> action (default zero)")
        p.add_argument("--duration", type=number(0.0, 1e6, low_open=True, unit="s"), required=True,
                       metavar="S", help="simulated seconds to run")
        p.add_argument("--env-arg", dest="env_args", action="append", default=[], metavar="KEY=VALUE",
                       help="an argument of the environment's constructor "
                            "(repeatable; VALUE read as JSON, else as text), "
                            "e.g. terminate_when_unhealthy=false")
        heat = p.add_mutually_exclusive_group()
        heat.add_argument("--models", default=None, metavar="MODEL.json",
                          help="saved models (fit or diagnose --save): by "
                               "joint name, or one actuator's for every joint")
        heat.add_argument("--plant", choices=sorted(PLANTS), default=None, help="the suite's plant with "
                          "this datasheet actuator at every joint (default x8-16)")
        p.add_argument("--actuator", default=None, metavar="NAME",
                       help="with --models: the model file's actuator whose model serves every joint")
        p.add_argument("--torque-constant", dest="torque_constant",
                       type=number(0.0, 1e4, low_open=True, unit="N m/A"), default=None, metavar="NM_PER_A",
                       help="for a model that heats from a current (A or "
                       "mA): the motor's torque constant at the joint, "
                       "N m per A, by which the environment's torques become currents")
        p.add_argument("--joints", default=None, metavar="A,B,...", help="the joints to heat (default every "
                       "one)")
        add_temperature(p, "--limit-C",
                        "every joint's limit (default: the models' stored limits, or the plant's)")
        p.add_argument("--ambient-C", dest="ambient_C", type=number(-60.0, 150.0, unit="degC"), default=25.0,
                       metavar="C", help="the air's temperature, and the joints' at the start (default 25)")
        p.add_argument("--seed", type=SEED, default=0, help="seed of the environment and of a random policy")
        p.add_argument("--plot", type=output_dir, default=None, metavar="DIR",
                       help="write audit.png (every joint's temperature over time) into DIR")
        p.add_argument("--json", action="store_true", help="the report as JSON")
        add_terms(p)

    def work(self, args) -> Outcome:
        from ..envs.audit import audit
        from ..model.saved import ModelFile
        from .reading import load_terms

        load_terms(args)
        if args.plot:
            from ..plotting.inventory import read_inventory
            from ..util.atomic import replaces

            replaces(args.plot / "audit.png", lambda p: read_inventory(p) is not None, "--plot")
        heat = {}
        if args.actuator and not args.models:
            raise UsageError("--actuator names the model file's actuator: give --models MODEL.json")
        if args.models:
            models = ModelFile.load(args.models)
            for note in models.notes:
                say(note)
            heat["models"] = models[args.actuator] if args.actuator else models
            heat["torque_constant_Nm_per_A"] = args.torque_constant
        elif args.torque_constant is not None:
            raise UsageError(
                "--torque-constant turns torques into the current a model heats from: give --models"
            )
        else:
            from .. import plant

            heat["plant"] = getattr(plant, PLANTS[args.plant or "x8-16"])
        joints = [j.strip() for j in args.joints.split(",") if j.strip()] if args.joints else None
        result = audit(args.env, args.policy, args.duration, seed=args.seed,
                       env_kwargs=env_kwargs(args.env_args), joints=joints, limit_C=args.limit_C,
                       ambient_C=args.ambient_C, **heat)
        if args.plot:
            from ..plotting.audit import plot_audit

            plot_audit(result, args.plot / "audit.png")
        return Outcome(result.to_json(), "\n".join(result.lines()))


add_parser = Audit().add_parser


def env_kwargs(pairs: list[str]) -> dict:
    """``KEY=VALUE`` pairs as keyword arguments: VALUE read as JSON (``false``, ``0.5``, ``[1, 2]``), else
    text."""
    out = {}
    for pair in pairs:
        key, eq, value = pair.partition("=")
        if not eq or not key.strip().isidentifier():
            raise UsageError(f"--env-arg {pair}: expected KEY=VALUE with KEY an argument name, e.g. "
                             f"terminate_when_unhealthy=false")
        try:
            out[key.strip()] = json.loads(value)
        except json.JSONDecodeError:
            out[key.strip()] = value
    return out

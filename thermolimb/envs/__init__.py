"""What the suite's Gymnasium environments share, independent of any robot.

Environments live with their robots and register when the robot package is imported, as Gymnasium's
third-party environments do: after importing the ``hexapod_pb`` package,
``gymnasium.make("thermolimb/HexapodLoadCarry-v0")`` works (or
``gymnasium.make("hexapod_pb:thermolimb/HexapodLoadCarry-v0")``, which imports the package itself).  This
package never imports a robot.  ``import thermolimb`` neither imports Gymnasium nor registers anything.  Here:
the robot packages that provide environments (found through the ``thermolimb.envs`` entry-point group),
registration with the policies each environment offers, the rig base environment (:mod:`.base`), policies by
name (:mod:`.policies`) seeded episodes (:mod:`.episodes`) and their tables and plots (:mod:`.tables`).
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import import_module
from importlib.metadata import entry_points

from ..util.errors import UsageError

ENTRY_POINT_GROUP = "thermolimb.envs"


@dataclass(frozen=True)
class EnvInfo:
    """An environment of the suite: its id, its class and the module holding its named policies."""

    env_id: str
    entry_point: str  # "module:Class"
    policies: str  # a module with POLICIES = {name: factory(seed) -> policy}


ENVS: dict[str, EnvInfo] = {}


def register_env(env_id: str, entry_point: str, policies: str) -> None:
    """Register ``env_id`` with Gymnasium (by string entry point, nothing is imported) and with the suite."""
    import gymnasium as gym

    if env_id not in gym.registry:
        gym.register(env_id, entry_point=entry_point)
    ENVS[env_id] = EnvInfo(env_id, entry_point, policies)


def known_envs() -> dict[str, EnvInfo]:
    """Every environment of the installed robot packages (importing each package registers its own)."""
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        import_module(ep.value)
    return ENVS


def env_info(env_id: str) -> EnvInfo:
    envs = known_envs()
    if env_id not in envs:
        raise UsageError(f"unknown environment {env_id!r}; expected one of {', '.join(sorted(envs))}")
    return envs[env_id]


def env_class(env_id: str) -> type:
    module, _, name = env_info(env_id).entry_point.partition(":")
    return getattr(import_module(module), name)


def __getattr__(name: str):
    """``thermolimb.envs.ThermalWrapper``, imported when first asked for (it imports Gymnasium and the
    model)."""
    if name == "ThermalWrapper":
        from .thermal_wrapper import ThermalWrapper

        return ThermalWrapper
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

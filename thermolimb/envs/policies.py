"""Strategies as policies: ``policy(env, observation) -> action``, made by name for an environment.

Each robot package names its strategies in a ``POLICIES`` mapping
(``name -> factory(seed) -> policy``) in the module given when its
environment was registered; ``random`` is offered for every environment.  A
policy that plans reads the robot's state from ``env.unwrapped`` (what the
controller on the rig would know: configuration and measured temperatures).
"""

from __future__ import annotations

from importlib import import_module
from typing import Callable

import numpy as np

from ..util.errors import UsageError
from . import env_info

Policy = Callable[[object, np.ndarray], object]


class RandomPolicy:
    """Uniform actions from the action space, with its own seeded generator."""

    def __init__(self, seed: int = 0):
        self.seed = seed
        self._seeded = False

    def __call__(self, env, observation):
        space = env.action_space
        if not self._seeded:
            space.seed(self.seed)
            self._seeded = True
        return space.sample()


def constant_policy(action) -> Callable[[int], Policy]:
    """A factory of policies that always take ``action``."""
    return lambda seed=0: (lambda env, observation: action)


def strategies(env_id: str) -> tuple[str, ...]:
    """The named strategies of an environment, ``random`` last."""
    return (*_factories(env_id), "random")


def make_policy(env_id: str, name: str, seed: int = 0) -> Policy:
    """A fresh policy by name for an environment id."""
    if name == "random":
        return RandomPolicy(seed)
    factories = _factories(env_id)
    if name not in factories:
        raise UsageError(f"no strategy {name!r} for {env_id}; available: {', '.join(strategies(env_id))}")
    return factories[name](seed)


def _factories(env_id: str) -> dict[str, Callable[[int], Policy]]:
    return import_module(env_info(env_id).policies).POLICIES

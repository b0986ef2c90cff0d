"""A thermal audit of a policy: will it overheat a joint, which one, and when?

:func:`audit` runs a policy for a stretch of simulated time in an environment wrapped with
:class:`~.thermal_wrapper.ThermalWrapper` and keeps every joint's temperature.  The heat is carried across
episodes (a robot that falls and is set up again is still warm); each reset of the environment is counted, and
an environment made from its id has no episode time limit (the policy runs for the audit's whole duration).
The report per joint: the peak temperature, the first time it reached its limit (or none within the run), and
which joint limits the run -- the first to reach its limit, else the one closest to it.
"""

from __future__ import annotations

import contextlib
import inspect
import math
import sys
from dataclasses import dataclass, field
from importlib import import_module
from typing import Callable

import gymnasium as gym
import numpy as np

from ..model.experience import MARGIN, MARGIN_K
from ..util.errors import UsageError
from .thermal_wrapper import ThermalWrapper


@dataclass
class AuditResult:
    """What :func:`audit` saw: each joint's temperature at every step, and the limits it was held to."""

    env_id: str
    policy: str
    joints: tuple[str, ...]
    time_s: np.ndarray
    temperature_C: np.ndarray  # (steps + 1, joints)
    limit_C: np.ndarray
    resets: int
    heat: str  # what heated the joints, in words
    notes: list[str] = field(default_factory=list)

    @property
    def duration_s(self) -> float:
        return float(self.time_s[-1])

    def first_at_limit_s(self) -> list[float | None]:
        out = []
        for k in range(len(self.joints)):
            hit = np.flatnonzero(self.temperature_C[:, k] >= self.limit_C[k])
            out.append(float(self.time_s[hit[0]]) if hit.size else None)
        return out

    def limiting_joint(self) -> str:
        """The first joint to reach its limit; if none did, the one that came closest."""
        reached = [(t, j) for t, j in zip(self.first_at_limit_s(), self.joints) if t is not None]
        if reached:
            return min(reached)[1]
        margin = self.limit_C - self.temperature_C.max(axis=0)
        return self.joints[int(np.argmin(margin))]

    def rows(self) -> list[dict]:
        peak = self.temperature_C.max(axis=0)
        return [{"joint": j, "peak_C": float(peak[k]), "limit_C": float(self.limit_C[k]),
                 "time_to_limit_s": t} for k, (j, t) in enumerate(zip(self.joints, self.first_at_limit_s()))]

    def to_json(self) -> dict:
        return {
            "env": self.env_id,
            "policy": self.policy,
            "duration_s": self.duration_s,
            "resets": self.resets,
            "heat": self.heat,
            "limiting_joint": self.limiting_joint(),
            "joints": self.rows(),
            "notes": list(self.notes),
        }

    def lines(self) -> list[str]:
        """The report in words, one joint per line, hottest first."""
        rows = sorted(self.rows(), key=lambda r: -r["peak_C"])
        width = max(len(r["joint"]) for r in rows)
        out = [f"{self.env_id}, policy {self.policy}: {self.duration_s:.0f} s simulated "
               f"({self.resets} reset{'s' if self.resets != 1 else ''}), heat from {self.heat}"]
        for r in rows:
            when = (f"reaches {r['limit_C']:.0f} degC at {r['time_to_limit_s']:.0f} s"
                    if r["time_to_limit_s"] is not None else f"not at {r['limit_C']:.0f} degC within "
                                                             f"{self.duration_s:.0f} s")
            out.append(f"  {r['joint']:{width}s}  peak {r['peak_C']:6.1f} degC  {when}")
        first = self.first_at_limit_s()
        limiting = self.limiting_joint()
        out.append(f"limiting joint: {limiting}" + ("" if any(t is not None for t in first) else
                                                    " (closest to its limit; none reached it)"))
        return out + [f"note: {n}" for n in self.notes]


def load_policy(text: str, seed: int) -> Callable:
    """``zero``, ``random`` (seeded) or ``MODULE:CALLABLE``, a function ``(env, observation) -> action`` -- a
    module of the user's, imported because the user names it."""
    if text == "zero":
        return lambda env, observation: np.zeros(env.action_space.shape, env.action_space.dtype)
    if text == "random":
        from .policies import RandomPolicy

        return RandomPolicy(seed)
    module, _, name = text.partition(":")
    if not module or not name:
        raise UsageError(f"--policy {text}: expected zero, random or "
                         "MODULE:CALLABLE (a function (env, observation) "
                         f"-> action)")
    try:
        policy = getattr(import_module(module), name)
    except ImportError as exc:
        raise UsageError(f"--policy {text}: cannot import {module} ({exc})") from None
    except AttributeError:
        raise UsageError(f"--policy {text}: {module} has no {name}") from None
    if not callable(policy):
        raise UsageError(f"--policy {text}: {name} is not callable; "
                         "expected a function (env, observation) -> action")
    try:
        signature = inspect.signature(policy)
    except ValueError:  # a compiled callable with no signature to read: its first call will tell
        return policy
    try:
        signature.bind(None, None)
    except TypeError as exc:
        raise UsageError(f"--policy {text}: {name} cannot be called as "
                         f"{name}(env, observation) ({exc}); expected a "
                         f"function (env, observation) -> action") from None
    return policy


def audit(env: gym.Env | str, policy: Callable | str, duration_s: float, seed: int = 0, env_kwargs=None,
          **wrapper) -> AuditResult:
    """Run ``policy`` for ``duration_s`` of simulated time in ``env`` (an id or an environment) wrapped with
    :class:`ThermalWrapper` (``wrapper``: its arguments); the temperatures of every step."""
    env_id = env if isinstance(env, str) else (env.spec.id if env.spec else type(env.unwrapped).__name__)
    name = policy if isinstance(policy, str) else getattr(policy, "__name__", type(policy).__name__)
    if isinstance(policy, str):
        policy = load_policy(policy, seed)
    if not (math.isfinite(duration_s) and duration_s > 0):
        raise UsageError(f"--duration must be a positive number of seconds, got {duration_s!r}")
    if isinstance(env, str):
        from . import known_envs

        known_envs()  # the suite's robots register their environments
        env = _made(env, env_id, env_kwargs or {})
    wrapped = ThermalWrapper(env, observe=None, reset_heat=False, **wrapper)
    heat = (
        "the models given"
        if wrapper.get("models") is not None
        else "the suite's plant with datasheet actuators"
    )
    steps = int(math.ceil(duration_s / wrapped.dt_s))
    strongest = np.zeros(len(wrapped.joints))  # each joint's largest |torque|, N m
    resets = 0
    try:
        observation, info = wrapped.reset(seed=seed)
        temperatures = [info["temperature_C"]]
        for step in range(steps):
            action = _action(policy, name, wrapped, observation, step)
            try:
                observation, _, terminated, truncated, info = wrapped.step(action)
            except UsageError:
                raise
            except Exception as exc:  # noqa: BLE001 -- the environment, made with the user's arguments
                given = ", ".join(f"{k}={v!r}" for k, v in (env_kwargs or {}).items())
                raise UsageError(f"--env {env_id} failed at step {step}: {type(exc).__name__}: "
                                 f"{str(exc).splitlines()[0] if str(exc) else 'no message'}"
                                 + (f" (made with {given}: check those values)" if given else "")) from None
            temperatures.append(info["temperature_C"])
            strongest = np.maximum(strongest, np.abs(info["torque_Nm"]))
            if terminated or truncated:
                observation, _ = wrapped.reset()
                resets += 1
    finally:
        wrapped.close()
    time_s = np.arange(steps + 1) * wrapped.dt_s
    temperatures = np.array(temperatures)
    notes = beyond_experience(wrapped.joints, getattr(wrapped.heat, "experience", None), strongest,
                              temperatures.max(axis=0))
    peak = getattr(wrapped.heat, "peak_Nm", None)
    if peak is not None and np.any(strongest > 1.001 * peak):
        over = strongest > 1.001 * peak
        k = int(np.argmax(np.where(over, strongest / peak, 0.0)))
        notes.append(f"{int(over.sum())} of {len(over)} joints were "
                     "given more torque than their actuator's peak (the "
                     f"most, {wrapped.joints[k]}: {strongest[k]:.3g} "
                     f"N m against {peak[k]:.3g} N m); the plant heats "
                     f"them at the peak, as a drive that holds it would")
    return AuditResult(env_id, name, wrapped.joints, time_s, temperatures, wrapped.limit_C, resets, heat,
                       notes)


def _made(env_id: str, shown: str, kwargs: dict) -> gym.Env:
    """``gym.make(env_id, **kwargs)`` with no episode time limit (the policy runs for the audit's duration,
    reset only when an episode ends); whatever the environment's constructor refuses in the user's arguments
    is one sentence.  No window is opened: the audit runs where no display may be."""
    bad = [k for k, v in kwargs.items() if isinstance(v, float) and not math.isfinite(v)]
    if bad:
        raise UsageError(f"--env-arg {bad[0]}={kwargs[bad[0]]}: expected a finite number")
    if kwargs.get("render_mode") not in (None, "rgb_array", "depth_array"):
        raise UsageError(f"--env-arg render_mode={kwargs['render_mode']}: "
                         "the audit draws no window (a display may "
                         f"not be there); leave render_mode out, or give rgb_array")
    try:
        return gym.make(env_id, max_episode_steps=2**31 - 1, **kwargs)
    except gym.error.Error as exc:
        raise UsageError(f"--env {shown}: {exc}") from None
    except TypeError as exc:  # an argument its constructor does not take
        raise UsageError(
            f"--env {shown} does not take the arguments given ({exc}); see help(env.unwrapped)"
        ) from None
    except Exception as exc:  # noqa: BLE001 -- the user's arguments reach the environment's own code
        given = ", ".join(f"{k}={v!r}" for k, v in kwargs.items()) or "no arguments"
        raise UsageError(
            f"--env {shown} could not be made with {given}: {type(exc).__name__}: "
            f"{str(exc).splitlines()[0] if str(exc) else 'no message'}"
        ) from None


def _action(policy: Callable, name: str, env: gym.Env, observation, step: int) -> np.ndarray:
    """The policy's action at ``step``, checked: what it prints goes to standard error (standard output
    carries the audit, and its JSON); an exception, None, the wrong shape or a value that is not finite is one
    sentence naming the step and what was expected."""
    space = env.action_space
    try:
        with contextlib.redirect_stdout(sys.stderr):
            action = policy(env, observation)
    except Exception as exc:  # noqa: BLE001 -- the user's policy: any of its errors is said, not a traceback
        raise UsageError(f"--policy {name} raised {type(exc).__name__} at step {step}: {exc}") from None
    expected = f"expected an action of shape {space.shape} of finite numbers"
    try:
        values = np.asarray(action, dtype=float)
    except (TypeError, ValueError):
        values = None
    if action is None or values is None or values.shape != space.shape:
        got = (
            "None"
            if action is None
            else (f"shape {values.shape}" if values is not None else repr(action)[:60])
        )
        raise UsageError(f"--policy {name} returned {got} at step {step}; {expected}")
    if not np.isfinite(values).all():
        raise UsageError(f"--policy {name} returned "
                         f"{int((~np.isfinite(values)).sum())} value(s) that are not "
                         f"finite (NaN or inf) at step {step}; {expected}")
    return np.asarray(action, dtype=space.dtype) if getattr(space, "dtype", None) is not None else values


def beyond_experience(joints, experience, strongest_Nm, peak_C) -> list[str]:
    """Where the run took a model beyond the log it was identified on (the torque's or the temperature's range
    in the model file's provenance): its temperatures there are the model extrapolated, said once per kind."""
    if experience is None:
        return []
    torque, hot = [], []
    for joint, ranges, tau, peak in zip(joints, experience, strongest_Nm, peak_C):
        effort = ranges.get("effort")
        if effort and tau > (1.0 + MARGIN) * max(abs(effort[0]), abs(effort[1])):
            torque.append((tau / max(abs(effort[0]), abs(effort[1]), 1e-12), joint, tau, effort))
        seen = ranges.get("temperature_C")
        if seen and peak > seen[1] + MARGIN_K:
            hot.append((joint, peak, seen[1]))
    notes = []
    if torque:
        ratio, joint, tau, effort = max(torque)
        notes.append(f"{len(torque)} of {len(joints)} joints were driven "
                     "beyond the torques their model was identified "
                     f"on (the most, {joint}: up to {tau:.3g} N m, "
                     f"{ratio:.2g} times the log's largest |effort| of "
                     f"{max(abs(effort[0]), abs(effort[1])):.3g}): "
                     "their temperatures are the model extrapolated")
    if hot:
        joint, peak, seen = max(hot, key=lambda h: h[1] - h[2])
        notes.append(f"{len(hot)} of {len(joints)} joints ran hotter "
                     "than any reading their model was identified on "
                     f"(the most, {joint}: {peak:.1f} degC against {seen:.1f} degC)")
    return notes

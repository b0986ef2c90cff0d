"""What every environment of the suite shares: a robot world rebuilt at every reset, decisions at a fixed
rate, actions checked against the action space, episodes that end, rendering offscreen, closing once."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np


def checked_port(live) -> int | None:
    """``live``: ``None``, or the port of the live view (0: any free port), or a ValueError naming it."""
    if live is None:
        return None
    if isinstance(live, bool) or not isinstance(live, int) or not 0 <= live <= 65535:
        raise ValueError(f"live must be None or a port number 0..65535 (0: any free port), got {live!r}")
    return live


def checked_finite(**values) -> None:
    """Reward weights, penalties and thresholds: each a finite number, or a ValueError naming it."""
    for name, value in values.items():
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
                or not math.isfinite(value):
            raise ValueError(f"{name} must be a finite number, got {value!r}")


def checked_range(name: str, value, lowest: float, highest: float) -> tuple[float, float]:
    """A reset range ``(low, high)`` with ``lowest <= low <= high <= highest``, or a ValueError naming it."""
    try:
        low, high = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a pair (low, high) of numbers, got {value!r}") from None
    if not (math.isfinite(low) and math.isfinite(high) and lowest <= low <= high <= highest):
        raise ValueError(f"{name} must satisfy {lowest:g} <= low <= "
                         f"high <= {highest:g}, got ({low:g}, {high:g})")
    return low, high


class RigEnv(gym.Env):
    """Base of the suite's environments: ``self.sim`` is the current world (a
    :class:`thermolimb.rig.BulletRig`).

    Subclasses call :meth:`_begin_step` first in ``step`` (it checks the
    action and returns it as an array) and :meth:`_end_step` last (it
    counts decision steps and says whether the episode is truncated).  An
    episode of ``max_time_s`` has ``ceil(max_time_s / decision_s)`` decision
    steps; stepping after it ended, or with an action the action space does
    not contain (non-finite numbers, a mode out of range), raises a
    ``ValueError`` or ``RuntimeError`` naming what is wrong, and the
    environment stays usable.  Copying or pickling one whose world is live
    is refused in one sentence (the copy would share its PyBullet client).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 1}
    # the keys ``reset(options=...)`` accepts (documented by each environment)
    RESET_OPTIONS: tuple[str, ...] = ()
    JOINTS: tuple[str, ...] = ()  # the robot's joints, in the rig's order (known before the first reset)
    # control steps of rig log kept in memory: an episode's memory stays flat however long
    LOG_CAPACITY = 3000

    def __init__(self, max_time_s: float, decision_s: float, render_mode: str | None = None):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        for name, value in (("max_time_s", max_time_s), ("decision_s", decision_s)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be a positive, finite number of seconds, got {value!r}")
        self.render_mode = render_mode
        self.max_time_s = float(max_time_s)
        self.decision_s = float(decision_s)
        self.max_steps = math.ceil(self.max_time_s / self.decision_s - 1e-9)
        self.sim = None
        self.steps = 0
        self._ended = False
        self.live = None  # a port: the world of every episode streamed live (thermolimb.monitor.live)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        if options is not None:
            if not isinstance(options, dict):
                raise ValueError(f"reset options must be a dict or None, got {type(options).__name__}")
            unknown = sorted(str(k) for k in options if k not in self.RESET_OPTIONS)
            if unknown:
                accepted = ", ".join(self.RESET_OPTIONS) or "none"
                raise ValueError(f"{type(self).__name__}.reset does not "
                                 f"take the option(s) {', '.join(unknown)}; "
                                 f"it takes: {accepted}")
        super().reset(seed=seed)
        self.close()
        self.steps = 0
        self._ended = False

    def __reduce_ex__(self, protocol):
        """Copying or pickling an environment whose world is live is refused in one sentence: the copy would
        share the original's PyBullet client (stepping one moves the other, closing one kills both)."""
        if self.sim is not None:
            raise TypeError(f"a {type(self).__name__} with a live PyBullet "
                            "world cannot be copied or pickled (the "
                            "copy would share its physics client); make "
                            "another with gymnasium.make, or copy it "
                            f"before reset() or after close()")
        return super().__reduce_ex__(protocol)

    def _begin_step(self, action) -> np.ndarray:
        if self.sim is None:
            raise RuntimeError("call reset() before step()")
        if self.live is not None and self.sim.stream is None:
            from ..monitor.live import RigStream, live_view

            self.sim.stream = RigStream(live_view(self.live))
        if self._ended:
            raise RuntimeError("the episode has ended (terminated or truncated); call reset() before step()")
        space = self.action_space
        if isinstance(space, gym.spaces.Discrete):
            value = np.asarray(action)
            if value.shape != () or value.dtype.kind not in "biuf" or not np.isfinite(value) \
                    or value != np.round(value) or not space.contains(int(value)):
                raise ValueError("action must be a whole number from "
                                 f"{space.start} to {space.start + space.n - 1}, "
                                 f"got {action!r}")
            return np.asarray(int(value))
        raw = np.asarray(action)
        if raw.dtype.kind not in "biuf":
            raise ValueError(f"action must hold real numbers, got {raw.dtype} ({action!r:.80})")
        value = raw.astype(float)
        if value.shape != space.shape:
            raise ValueError(f"action must have shape {space.shape}, got {value.shape}")
        if not np.all(np.isfinite(value)):
            raise ValueError(f"action must be finite, got {value.tolist()}")
        return value

    def _end_step(self, terminated: bool) -> bool:
        """Count the step; whether the episode is truncated (time is up and it did not terminate)."""
        self.steps += 1
        truncated = (not terminated) and self.steps >= self.max_steps
        self._ended = terminated or truncated
        return truncated

    def close(self):
        if self.sim is not None:
            self.sim.close()
            self.sim = None

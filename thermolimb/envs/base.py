"""What both environments share: a robot world rebuilt at every reset, rendered offscreen, closed once."""

from __future__ import annotations

import gymnasium as gym


class RigEnv(gym.Env):
    """Base of the suite's environments: ``self.sim`` is the current world (a :class:`thermolimb.rig.BulletRig`)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 1}

    def __init__(self, render_mode: str | None = None):
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        self.render_mode = render_mode
        self.sim = None

    def _require_reset(self) -> None:
        if self.sim is None:
            raise RuntimeError("call reset() before step()")

    def close(self):
        if self.sim is not None:
            self.sim.close()
            self.sim = None

"""A simulated robot watched exactly like a real one: the rig's plant published on the monitor's channels.

Every :class:`~thermolimb.rig.BulletRig` publishes, when asked, what its thermal protection knows at each
control period -- the winding observer's estimate and uncertainty, the time to the winding limit at the
current current and speed, the derating, the thermistor's reading -- as the
:class:`~thermolimb.monitor.Estimate` records ``thermolimb monitor`` publishes, on the same Foxglove topics
(:mod:`.outputs`).  One Foxglove server per process (:func:`live_view`), whichever rigs come and go
(an environment makes a new world at every reset).

Ask with ``THERMOLIMB_LIVE=PORT`` in the environment (every rig of the process, e.g. ``thermolimb demo
hexapod-walk --live``), with ``gymnasium.make(..., live=PORT)`` for an environment, or
``rig.stream = RigStream(live_view(PORT))``.
"""

from __future__ import annotations

import os
import sys

import numpy as np

from .estimator import Estimate, level
from .outputs import FoxgloveOutput

ENV_VARIABLE = "THERMOLIMB_LIVE"
PUBLISH_EVERY_S = 0.1  # of simulated time
HORIZON_S = 3600.0  # the forecast's horizon (s); beyond it: never at this effort

_VIEWS: dict[int, FoxgloveOutput] = {}
_REFUSED: set[str] = set()


def live_view(port: int) -> FoxgloveOutput:
    """The process's Foxglove server on ``port`` (made on the first call)."""
    if port not in _VIEWS:
        _VIEWS[port] = FoxgloveOutput(port, [])  # its channels come with the actuators it is given
        print(f"note: live view: open ws://127.0.0.1:{_VIEWS[port].port} in Foxglove", file=sys.stderr)
    return _VIEWS[port]


def from_environment():
    """A :class:`RigStream` when ``THERMOLIMB_LIVE`` asks for one, else ``None``.  A process that cannot serve
    (the port taken by another process of the same run, the SDK missing) says so once and runs unwatched."""
    port = os.environ.get(ENV_VARIABLE)
    if not port or port in _REFUSED:
        return None
    try:
        return RigStream(live_view(int(port)))
    except ValueError:
        raise ValueError(f"{ENV_VARIABLE}={port!r}: expected a port number") from None
    except Exception as exc:  # noqa: BLE001 -- a live view is optional: the simulation goes on without it
        _REFUSED.add(port)
        print(f"note: no live view in this process ({exc})", file=sys.stderr)
        return None


class RigStream:
    """Publishes a rig's plant every :data:`PUBLISH_EVERY_S` of simulated time."""

    def __init__(self, view, every_s: float = PUBLISH_EVERY_S):
        self.view = view
        self.every_s = every_s
        self.next_s = 0.0

    def publish(self, rig) -> None:
        if rig.time_s + 1e-9 < self.next_s:
            return
        self.next_s = rig.time_s + self.every_s
        plant = rig.plant
        measured = plant.measured_C
        limits = plant.winding_limits_C
        if plant.observer is not None:
            winding, std = plant.observer.winding_C, plant.observer.winding_std_K
            q, qd = rig.joint_states()
            ttl = plant.observer.time_to_limit_s(plant.current_A, limits, plant.ambient_C,
                                                 rig.actuator_velocities(q, qd), horizon_s=HORIZON_S)
        else:
            winding, std, ttl = measured, np.zeros_like(measured), [None] * plant.n
        derating = plant.derating()
        estimates = [
            Estimate(
                name,
                float(rig.time_s),
                float(measured[i]),
                float(winding[i]),
                float(std[i]),
                ttl[i],
                float(derating[i]),
                level(winding[i], limits[i], derating[i], ttl[i]),
                float(limits[i]),
            )
            for i, name in enumerate(plant.names)
        ]
        self.view.publish(estimates, {name: "the rig's winding observer" for name in plant.names})

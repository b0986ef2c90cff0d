"""The hexapod's fixed-rate control loop: the one place a controller step meets the rig.

The environment, the load-carrying scenarios and the endurance runs all step
the robot through a :class:`ControlLoop`, and all settle it the same way
(standing still for ``SETTLE_S`` after a reset, before anything is
measured).  The controller itself stays a pure function
(:func:`~hexapod_pb.controller.control_step`); the loop only holds its state.
"""

from __future__ import annotations

from collections import Counter

import numpy as np

from ..params import DAISY, FALLEN_BODY_HEIGHT_M, SETTLE_S, DaisyParams
from ..readings import Reading
from ..sim import HexapodSim
from . import cpg
from .controller import ControllerState, Gains, ThermalContext, control_step
from .stance import StanceSolution


class ControlLoop:
    """The controller's state on one rig, stepped one control period at a time.

    ``forces`` (each step) is a stance-force strategy's name or a blend
    ``{name: weight}``; ``gait`` may change from step to step (the
    environment scales its step length with the agent's speed).
    """

    def __init__(self, sim: HexapodSim, params: DaisyParams = DAISY, gait: cpg.CPGParams | None = None,
                 payload_kg: float = 0.0, gains: Gains = Gains(), thermal: ThermalContext | None = None):
        self.sim = sim
        self.params = params
        self.gait = gait or cpg.CPGParams()
        self.payload_kg = payload_kg
        self.gains = gains
        self.thermal = thermal
        self.state = ControllerState(cpg.initial_state(None, self.gait))
        self.reading: Reading = sim.read()
        self.torques_Nm = np.zeros(len(params.effort_limit_Nm))  # what the controller commanded last
        self.solution: StanceSolution | None = None  # the stance forces of the last control period
        self.solvers: Counter[str] = Counter()  # control periods per stance solution's label (what solved it)
        self.fallbacks = 0  # control periods whose stance forces a fallback solver produced

    @property
    def fallen(self) -> bool:
        return bool(self.reading.body_position_m[2] < FALLEN_BODY_HEIGHT_M)

    def step(self, forces, walking: bool = True, gait: cpg.CPGParams | None = None) -> Reading:
        """One control period: the controller's torques from the last reading, held on the rig."""
        self.torques_Nm, self.state, info = control_step(
            self.reading, self.state, self.params, gait or self.gait, forces, self.sim.config.control_dt_s,
            self.payload_kg, self.gains, self.thermal, walking=walking)
        self.solution = info["solution"]
        self.solvers[self.solution.label] += 1
        self.fallbacks += self.solution.fell_back
        self.reading = self.sim.step(self.torques_Nm)
        return self.reading

    def solver_note(self) -> str:
        """What solved the stance forces, in control periods (the run's log carries it)."""
        counts = ", ".join(f"{label}: {n}" for label, n in self.solvers.most_common())
        return f"stance forces ({sum(self.solvers.values())} control periods): {counts}"

    def settle(self, forces) -> Reading:
        """Stand still for ``SETTLE_S`` with ``forces``: the start every measured run shares."""
        for _ in range(int(SETTLE_S * self.sim.config.control_hz)):
            self.step(forces, walking=False)
        return self.reading

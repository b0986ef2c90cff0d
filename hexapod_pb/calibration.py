"""The hexapod's own calibration log and the first-order models identified from it (what its planners may
know)."""

from __future__ import annotations

import numpy as np

from thermolimb.identification.calibration import Calibration, identify_bank, measured_ambient_C
from thermolimb.model import ModelArrays

from .constants import JOINTS
from .control import cpg
from .control.loop import ControlLoop
from .params import DAISY
from .sim import HexapodSim, SimConfig
from .thermal import EFFECTS, PROTECTION

MIN_RISE_K = 0.5  # a joint whose log shows less mean Joule rise (five sensor steps) is not identified: prior
WINDING_RC_S = 1.0  # an X8 winding's own time constant is 1.4 s: the fastest an identified RC may be


def calibrate(duration_s: float, seed: int = 0, *, payload_kg: float = 20.0) -> Calibration:
    """The robot's own log: walking then standing with ``payload_kg`` at 25 degC; Eq. 5 identified from it
    (the bank in JOINTS order), and the ambient the robot measured when it started cold."""
    gait = cpg.CPGParams()
    config = SimConfig(payload_kg=payload_kg, ambient_C=25.0)
    with HexapodSim(config=config, plant_effects=EFFECTS, seed=seed, protection=PROTECTION) as sim:
        loop = ControlLoop(sim, DAISY, gait, payload_kg)
        n = int(round(duration_s * config.control_hz))
        for k in range(n):
            # walk, stand, walk, stand: efforts that change, so every walking joint is identifiable
            loop.step("vertical_only", walking=(4 * k // n) % 2 == 0)
        log = sim.thermal_log()
    # joule only: the X8 has no series-elastic bias to find, and a shoulder's torque never changes sign, so an
    # effort_bias term trades off against betaR on this log and extrapolates wildly
    bank = identify_bank(log, JOINTS, DAISY.effort_limit_Nm, min_rc_s=WINDING_RC_S, model="joule",
                         min_rise_K=MIN_RISE_K)
    return Calibration(bank, log, measured_ambient_C(log))


def at_ambient(bank: ModelArrays, ambient_C: float) -> ModelArrays:
    """The identified bank planning hours ahead at ``ambient_C``: every offset is the ambient the robot
    measures cold.

    Fitted on minutes of log, Eq. 5's offset holds whatever the first-order
    model could not follow -- here the housing's and body's warming, more
    for busy joints than idle ones -- and a minimax over predicted
    temperatures would shift load onto the joints the offsets call cool.
    Hours ahead the offset is the ambient.
    """
    return bank.replace(T_offset_C=np.full(bank.n, float(ambient_C)))

"""Thermal models of the hexapod's 18 actuators, for the thermal-aware distribution.

:func:`datasheet_bank` gives Eq. 5 from the actuator data: winding and
housing lumped, the body as the slow "ambient".
"""

from __future__ import annotations

import numpy as np

from thermolimb.model import FirstOrderBank
from thermolimb.plant import ACTUATOR_SPECS

from .constants import ACTUATOR_MODEL, JOINT_KINDS, JOINTS, LEGS


def datasheet_bank(ambient_C: float = 25.0) -> FirstOrderBank:
    """Eq. 5 parameters from the actuator data: RC = (C_w + C_h)(R_wh + R_hb), betaR = R_e (R_wh + R_hb) / k^2."""
    rc, beta = [], []
    for _ in LEGS:
        for kind in JOINT_KINDS:
            spec = ACTUATOR_SPECS[ACTUATOR_MODEL[kind]]
            net = spec.network
            r_th = net.resistance_K_per_W[0] + (net.resistance_K_per_W[1] if net.n_nodes > 1 else 0.0)
            c_th = net.capacity_J_per_K[0] + (net.capacity_J_per_K[1] if net.n_nodes > 1 else 0.0)
            rc.append(r_th * c_th)
            beta.append(spec.winding_resistance_ohm * r_th / spec.effort_per_amp**2)
    n = len(JOINTS)
    return FirstOrderBank(np.array(rc), np.array(beta), np.zeros(n), np.full(n, ambient_C))

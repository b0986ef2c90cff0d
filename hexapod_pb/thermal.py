"""Thermal models of the hexapod's 18 actuators, for the thermal-aware distribution.

:func:`datasheet_bank` gives Eq. 5 from the actuator data: winding and
housing lumped, the body as the slow "ambient".
"""

from __future__ import annotations

from thermolimb.model import FirstOrderBank

from .params import DAISY, DaisyParams


def datasheet_bank(ambient_C: float = 25.0, params: DaisyParams = DAISY) -> FirstOrderBank:
    """Eq. 5 parameters of every joint's actuator, winding and housing lumped (two nodes) on the slow body."""
    return FirstOrderBank.from_specs(params.joint_actuators, ambient_C, lumped_nodes=2)

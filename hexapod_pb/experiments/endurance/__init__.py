"""How long the hexapod works before an actuator derates: payload, ambient, walking or standing, by strategy.

A cell of the envelope is measured, not assumed: the robot runs in PyBullet
until its gait is periodic, one cycle (eight strides, or as long standing) of
its applied torques and joint speeds is recorded, and the plant's network is
propagated over hours through that cycle's exact affine map
(:class:`~thermolimb.plant.periodic.CycleMap`).  Strategies whose torques
depend on the temperatures (the thermal-aware ones) are propagated in windows,
the cycle re-measured at the start of each window with the plant put in the
propagated state.  Derating starts when a true winding reaches its limit less
the protection's margin (:class:`~thermolimb.plant.ThermalProtection`).

The plant is HEBI's three-node X8 network (winding, housing, a 2500 J/K
body) with copper resistance rising with temperature.  Its sensors read with noise and 0.1 K steps.

Thermal-aware strategies plan with models identified from the robot's own
calibration log (:func:`hexapod_pb.calibration.calibrate`), never with the plant's network:

``thermal_aware``
    the stance forces minimise the hottest predicted winding 20 s ahead (``wrench.thermal_minimax``);
``thermal_gait``
    the same forces, on a gait chosen before it starts: among duty factors,
    foot reaches, body heights and pauses that keep at least 80 % of the
    nominal speed, the one whose measured torques give the lowest hottest
    equilibrium with the identified models.

A pause is the gait's standing duty after every eight strides, measured in
PyBullet from the state the strides leave and joined to their cycle
(:meth:`~thermolimb.plant.periodic.CycleMap.followed_by`); the step between
walking and standing (the swing tripod put down) is not simulated.
"""

from .cells import STRATEGIES, THERMAL_STRATEGIES, CellResult, derating_threshold_C, endurance
from .check import PeriodicCheck, check_periodic
from .cycle import CYCLE_STRIDES, Cycle, cycle_steps, measure_cycle, pause_steps
from .gait import GAIT_CHOICES, MODES, NOMINAL_GAIT, Gait
from .planning import GaitPlan, plan_gait, predicted_peak_C

__all__ = [
    "CYCLE_STRIDES",
    "GAIT_CHOICES",
    "MODES",
    "NOMINAL_GAIT",
    "STRATEGIES",
    "THERMAL_STRATEGIES",
    "CellResult",
    "Cycle",
    "Gait",
    "GaitPlan",
    "PeriodicCheck",
    "check_periodic",
    "cycle_steps",
    "derating_threshold_C",
    "endurance",
    "measure_cycle",
    "pause_steps",
    "plan_gait",
    "predicted_peak_C",
]

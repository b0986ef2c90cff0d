"""The humanoid's thermal actuators: rotary motors at most joints, push-rod pairs at the ankles and waist.

Valkyrie's actuator thermal data is not public; the specs are calibrated to
what Jorgensen et al. report on hardware, in three steps:

1. Time constant.  Jorgensen et al. predict 20 s ahead and set that horizon to
   half the learned RC, so a winding's RC is 40 s: 20 J/K on 2 K/W, on a
   slow housing (2000 J/K, 1 K/W) that a two-minute experiment barely warms.
2. Heat scale.  Balancing on one leg heats the stance leg from 25 degC into
   the 75 degC warning zone "in less than two minutes".  Statics (Eq. 23 at
   the nominal single support, :mod:`humanoid_pb.model.statics`) says which
   actuator is: the stance ankle's push rods, at 24.7 % of the rod limit
   (the centre of mass sits over the sole's centre, 4 cm ahead of the ankle
   axis: the 125 kg above it * 9.81 m/s^2 * 0.04 m = 49 N m of pitch, 24 % of
   205 N m, shared by two rods on 3.7 cm arms), then the knee at 24.3 %
   (85 N m: bent 0.6 rad, it carries the body on a lever of about 7 cm),
   then the hip roll at 20.9 % (73 N m: the pelvis and the free leg held
   sideways over the stance hip); everything else is below 10 %.  Reaching
   75 degC from 25 degC after ``TIME_TO_WARNING_S`` = 100 s on the winding's
   RC needs a steady rise of 50 / (1 - e^(-100/40)) = 54.5 K, so the
   hottest actuator's copper loss is 54.5 K / 2 K/W = 27.2 W at 24.7 % of
   its limit, that is ``COPPER_LOSS_AT_30_PCT_W`` = 40 W at 30 % of the limit.
   The same rule sizes every actuator (effort per amp from its limit), so
   which actuator is hottest follows from the geometry, not from a choice.
3. Limit.  Valkyrie's actuators "can operate up to 90 degC": protection
   starts derating there, its margin below the winding limit
   (:mod:`humanoid_pb.limits`).

Jorgensen et al.'s Fig. 5 (the knee over squats every 4.5 minutes) would fix the
knee's own scale, but its temperatures are not in Jorgensen et al.'s text; the knee
is sized by the same rule as the rest (tests check the derivation).
"""

from __future__ import annotations

from thermolimb.model import ModelArrays
from thermolimb.plant import ActuatorSpec, ThermalNetwork

from .constants import ACTUATORS
from .limits import LIMITS
from .params import VALKYRIE, ValkyrieParams
from .scenarios import DEFAULT, Scenario
from .scenarios import scenario as get_scenario

# winding (tau = 20 J/K * 2 K/W = 40 s, Jorgensen et al.'s RC) on a slow housing (2000 J/K, 1 K/W)
VALKYRIE_NETWORK = ThermalNetwork(("winding", "housing"), (20.0, 2000.0), (2.0, 1.0))
TIME_TO_WARNING_S = 100.0  # single-leg balancing: 25 -> 75 degC at the hottest actuator's static effort


def actuator_specs(
    params: ValkyrieParams = VALKYRIE, scenario: str | Scenario = DEFAULT
) -> list[ActuatorSpec]:
    """One spec per actuator (ACTUATORS order): 0.5 ohm windings sized by the ``scenario``
    (:mod:`humanoid_pb.scenarios`; the default is the rule above, ``COPPER_LOSS_AT_30_PCT_W`` at 30 % of the
    limit)."""
    sizing = get_scenario(scenario)
    specs = []
    for name in ACTUATORS:
        limit = params.rod_force_limit_N if "_rod_" in name else params.effort_limit(name)
        per_amp = sizing.effort_per_amp(name, limit, 0.5)
        specs.append(
            ActuatorSpec(
                name.split("_")[-1],
                per_amp,
                0.5,
                limit,
                0.4 * limit,
                6.0,
                VALKYRIE_NETWORK,
                winding_limit_C=LIMITS.winding_C[ACTUATORS.index(name)],
                driver=None,
            )
        )
    return specs


def datasheet_bank(params: ValkyrieParams = VALKYRIE, ambient_C: float = 25.0,
                   scenario: str | Scenario = DEFAULT) -> ModelArrays:
    """Eq. 5 of every actuator from its data, without identification: the winding node on a housing at
    ambient.

    RC = C_w R_w (40 s) and betaR = R_e R_w / k^2: what a controller can plan
    with before it has a log of its own.
    """
    return ModelArrays.from_specs(actuator_specs(params, scenario), ambient_C, lumped_nodes=1)

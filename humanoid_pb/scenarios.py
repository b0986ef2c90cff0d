"""Recovery scenarios: the stance the humanoid balances in, and how its actuators are sized thermally.

``ankle``
    The stance of :func:`~humanoid_pb.ik.poses.crouch_angles` (0.3 rad: knees bent
    0.6 rad, the pelvis 3.7 cm below straight legs) and one sizing rule for every
    actuator (:mod:`humanoid_pb.thermal`'s derivation).  On one leg the stance
    ankle's push rods are the hottest (24.7 % of their limit, the knee 24.3 %),
    and double support unloads them almost completely: a case where switching to
    the cool foot does not pay.
``walking``
    The case Jorgensen et al. describe: Valkyrie balancing with bent knees at about its
    walking height, where the actuators that stay loaded in double support (the
    knees) are the hot ones.  Two changes, each stated with its source:

    * Stance: 0.45 rad (knees bent 0.9 rad; the pelvis 1.03 m above the ground,
      0.08 m below straight legs).  Assumed: Valkyrie's walking height is not in
      Jorgensen et al. or in ``facts.md``; 0.45 rad is the deepest of 0.35-0.5 rad at which
      this suite's balance controller holds one leg (at 0.5 rad the robot falls
      while lifting the free foot, measured).  Statics (Eq. 23) then put the stance
      knee at 44.5 % of its 350 N m limit on one leg and 27.3 % in double support,
      the ankle rods at 26.0 % and 1.8 %, the hip pitch at 6.5 % and 1.3 % (the
      trunk is upright over the hips here, so the hip pitch is not loaded as the
      issue's "knees and hip pitch" expects).
    * Sizing by actuator type.  Valkyrie's actuator types are public only through
      their effort limits (facts.md): one rotary type per limit (350 N m: hip roll,
      hip pitch, knee; 190 N m: hip yaw, torso yaw, shoulders; 65 N m: shoulder yaw,
      elbow; Jorgensen et al. call them harmonic-driven series-elastic actuators) and the
      linear push rods of the ankles and waist.  Their thermal ratings are not
      public.  Assumed: a rotary actuator holds 30 % of its peak limit continuously
      (the uniform rule's fraction), a push rod 45 % of its own: each rod's limit is
      already half of what one rod would need to hold its joint alone (the pair
      shares the load, facts.md), so the rod's motor is sized against a smaller
      peak.  The heat scale is then set by Jorgensen et al.'s calibration, as in the uniform
      rule: the hottest actuator on one leg reaches 75 degC from 25 degC in
      ``TIME_TO_WARNING_S`` (100 s), which needs 27.25 W in the hottest winding:
      27.25 W * (0.30 / 0.445)^2 = 12.4 W at a rotary actuator's continuous 30 %.

    The type assumption does not decide which actuator is hottest here: with one
    fraction for every type the knee (44.5 %) is still far ahead of the rods
    (26.0 %); ``tests/test_humanoid_model.py`` checks both rankings.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from thermolimb.util.frozen import FrozenMapping

from .constants import joint_kind

# actuator type of each joint kind, from Valkyrie's published effort limits (facts.md); rods are "linear"
ACTUATOR_TYPES = FrozenMapping(
    {
        "hip_roll": "rotary_350",
        "hip_pitch": "rotary_350",
        "knee": "rotary_350",
        "hip_yaw": "rotary_190",
        "torso_yaw": "rotary_190",
        "shoulder_pitch": "rotary_190",
        "shoulder_roll": "rotary_190",
        "shoulder_yaw": "rotary_65",
        "elbow": "rotary_65",
    }
)
TYPES = ("rotary_350", "rotary_190", "rotary_65", "linear")


def actuator_type(actuator: str) -> str:
    """``rotary_350``, ``rotary_190``, ``rotary_65`` or ``linear`` (a push rod)."""
    return "linear" if "_rod_" in actuator else ACTUATOR_TYPES[joint_kind(actuator)]


@dataclass(frozen=True)
class Scenario:
    """A stance and a thermal sizing: every actuator dissipates ``loss_at_continuous_W`` in its winding at its
    type's ``continuous_fraction`` of its effort limit, and ``loss_at_continuous_W (f / c)^2`` at a fraction
    ``f``."""

    name: str
    crouch_depth_rad: float
    loss_at_continuous_W: float
    continuous_fraction: FrozenMapping
    about: str
    # per-actuator continuous fractions that replace their type's (the switching map's thermally weak group)
    actuator_fraction: FrozenMapping = FrozenMapping({})

    def __post_init__(self):
        missing = [t for t in TYPES if t not in self.continuous_fraction]
        if missing:
            raise ValueError(f"Scenario {self.name!r}: no continuous fraction "
                             f"for actuator type(s) {', '.join(missing)}")
        if any(
            not 0.0 < f <= 1.0 for f in (*self.continuous_fraction.values(), *self.actuator_fraction.values())
        ):
            raise ValueError(f"Scenario {self.name!r}: continuous fractions must be in (0, 1]")
        if not 0.0 < self.crouch_depth_rad < 1.0:
            raise ValueError(f"Scenario {self.name!r}: crouch depth "
                             f"{self.crouch_depth_rad} rad; expected 0..1 rad")
        if not self.loss_at_continuous_W > 0.0:
            raise ValueError(f"Scenario {self.name!r}: loss_at_continuous_W must be positive")

    def effort_per_amp(self, actuator: str, limit: float, resistance_ohm: float) -> float:
        """The effort per amp that gives this sizing on a winding of ``resistance_ohm``: R (c limit / k)^2 =
        L."""
        c = self.actuator_fraction.get(actuator) or self.continuous_fraction[actuator_type(actuator)]
        return c * limit * np.sqrt(resistance_ohm / self.loss_at_continuous_W)


COPPER_LOSS_AT_30_PCT_W = 40.0  # the uniform rule, derived in humanoid_pb.thermal from TIME_TO_WARNING_S
UNIFORM = FrozenMapping(dict.fromkeys(TYPES, 0.3))
SCENARIOS = {
    "ankle": Scenario(
        "ankle",
        0.3,
        COPPER_LOSS_AT_30_PCT_W,
        UNIFORM,
        "the crouch (0.3 rad), one sizing for every actuator: the stance ankle's rods run hottest",
    ),
    # 27.25 W in the knee at 44.5 % of its limit on one leg: 27.25 * (0.30 / 0.445)^2 = 12.4 W at 30 %
    "walking": Scenario(
        "walking",
        0.45,
        12.4,
        FrozenMapping({"rotary_350": 0.30, "rotary_190": 0.30, "rotary_65": 0.30, "linear": 0.45}),
        "bent knees near walking height (0.45 rad), "
        "actuators sized by type: the stance knee runs "
        "hottest and stays loaded in double support",
    ),
}
DEFAULT = "ankle"


def scenario(name: str | Scenario) -> Scenario:
    """A scenario by name (or the scenario itself), with one clear error for an unknown name."""
    if isinstance(name, Scenario):
        return name
    if name not in SCENARIOS:
        raise ValueError(f"no humanoid scenario {name!r}; expected one of {', '.join(SCENARIOS)}")
    return SCENARIOS[name]

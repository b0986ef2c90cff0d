"""When does contact switching pay?  The recovery experiment over the hottest actuator group and the stance
height.

A cell of the map is a robot whose actuator group ``group`` (ankle rods, knee,
hip pitch, hip roll, torso) is the thermally weakest, balancing in a crouch of
depth ``depth_rad`` (hips and ankles ``-depth``, knees ``2 depth``; 0.15 rad is
the straightest stance the IK's working range allows, knees at its 0.3 rad
minimum, and 0.45 rad the deepest at which the balance controller holds one
leg).  Its quantity is the ratio of hot-set-safe times, minimum effort over
thermal-aware, from the same warning state: the time after the warning until
the heated stance leg and the weak group are below 70 degC (for a leg group this
is Jorgensen et al.'s hot-leg-safe time).  Above 1, switching pays.

Sizing of a cell (:func:`map_scenario`; a what-if, not Valkyrie's data):
statics (Eq. 23) at the nominal right single support of the crouch give each
actuator's fraction of its limit.  Every actuator outside the group is sized by
the uniform rule (its continuous rating at 30 % of its limit) with the heat
scale set so that the most loaded of them dissipates half of what reaches the
warning in ``time_to_warning_s``; the group's actuators get the continuous
fraction at which the group's most loaded one reaches the warning in that time.
So the group is the hottest at the warning by construction, whatever the
stance, and the other actuators are as warm as the loads make them.

Measured cells run Jorgensen et al.'s experiment in PyBullet (:func:`measure_cell`:
balance on the right leg to 75 degC, then each strategy).  To isolate the
physics of switching from identification, the thermal-aware planner plans here
with the datasheet models of the cell's actuators (:func:`datasheet_bank`), not
with identified ones.  :func:`predict_cell` is the first-order prediction of
the same experiment: the heating on the nominal single support by Eq. 5, each
strategy's first decision (the planner's mode and configuration, held with the
torques the IK chose), and each hot actuator's first-order cooling from its
warning temperature to 70 degC; transitions and re-planning are left out.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from thermolimb.util.frozen import FrozenMapping

from ..constants import ACTUATORS, TORSO_ACTUATORS, leg_actuators
from ..control.planner import ContactModePlanner
from ..ik.poses import crouch_angles, single_support, standing
from ..limits import LIMITS
from ..model.actuation import effort_limits
from ..model.statics import WholeBody
from ..params import VALKYRIE
from ..scenarios import UNIFORM, Scenario
from ..thermal import VALKYRIE_NETWORK, datasheet_bank
from .recovery import first_order_cooling_s, run_recovery

GROUPS = {
    "ankle rods": tuple(a for a in ACTUATORS if "_ankle_rod_" in a),
    "knee": tuple(a for a in ACTUATORS if a.endswith("_knee")),
    "hip pitch": tuple(a for a in ACTUATORS if a.endswith("_hip_pitch")),
    "hip roll": tuple(a for a in ACTUATORS if a.endswith("_hip_roll")),
    "torso": TORSO_ACTUATORS,
}
# straight (the IK's knee minimum) to the deepest one-leg stance
DEPTHS_RAD = (0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45)
HEAT_SIDE = "right"
AMBIENT_C = 25.0
# the most loaded actuator outside the group dissipates this share of the group's warning heat
OTHERS_SHARE = 0.5
STRATEGIES = ("thermal_aware", "minimum_effort")
# predictions fill unmeasured cells of a group only if they meet every measured cell within this
AGREEMENT = 0.10


def warning_loss_W(time_to_warning_s: float) -> float:
    """Winding loss that takes a first-order winding (the plant's node: 40 s, 2 K/W) from the ambient to the
    warning in ``time_to_warning_s``: (75 - 25) / (1 - exp(-t / RC)) / R."""
    c, r = VALKYRIE_NETWORK.capacity_J_per_K[0], VALKYRIE_NETWORK.resistance_K_per_W[0]
    return (LIMITS.warning_C - AMBIENT_C) / (1.0 - np.exp(-time_to_warning_s / (c * r))) / r


def hot_set(group: str) -> tuple[str, ...]:
    """The actuators a cell waits for: the heated stance leg and the weak group."""
    return tuple(dict.fromkeys(leg_actuators(HEAT_SIDE) + GROUPS[group]))


def _check(group: str, depth_rad: float) -> None:
    if group not in GROUPS:
        raise ValueError(f"no actuator group {group!r}; expected one of {', '.join(GROUPS)}")
    if not DEPTHS_RAD[0] <= depth_rad <= DEPTHS_RAD[-1]:
        raise ValueError(f"stance depth {depth_rad} rad is outside "
                         f"{DEPTHS_RAD[0]}-{DEPTHS_RAD[-1]} rad (the IK's "
                         f"straightest knee to the deepest stance the balance controller holds on one leg)")


def stance_fractions(body: WholeBody, depth_rad: float) -> np.ndarray:
    """Each actuator's |effort| / limit on the nominal right single support of the crouch (Eq. 23)."""
    q = single_support(body, standing(body, crouch_angles(depth_rad)), HEAT_SIDE)
    return np.abs(body.statics(q, HEAT_SIDE).efforts) / effort_limits(body.params)


def map_scenario(group: str, depth_rad: float, body: WholeBody | None = None,
                 time_to_warning_s: float = 100.0) -> Scenario:
    """The cell's robot (see the module docstring for the rule)."""
    _check(group, depth_rad)
    body = body or WholeBody()
    fractions = stance_fractions(body, depth_rad)
    inside = np.array([a in GROUPS[group] for a in ACTUATORS])
    hottest_other = float(fractions[~inside].max())
    hottest_group = float(fractions[inside].max())
    target = warning_loss_W(time_to_warning_s)
    loss = OTHERS_SHARE * target * (UNIFORM["rotary_350"] / hottest_other) ** 2  # W at the uniform 30 %
    weak = min(hottest_group * np.sqrt(loss / target), 1.0)  # the group's continuous fraction
    return Scenario(f"{group} at {depth_rad:.2f} rad", depth_rad, loss, UNIFORM,
                    f"{group} thermally weakest, crouch {depth_rad:.2f} rad",
                    FrozenMapping(dict.fromkeys(GROUPS[group], weak)))


@dataclass(frozen=True)
class Cell:
    """One cell: the hot-set-safe time of each strategy (s after the warning; None if not reached), the modes
    each chose, whether it fell, and the ratio minimum effort / thermal-aware."""

    group: str
    depth_rad: float
    source: str  # "measured" (PyBullet) or "first order"
    safe_s: dict
    modes: dict
    fell: dict
    warning_at_s: float | None
    watched_s: float | None = None  # measured: how long after the warning the runs went on

    @property
    def ratio_at_least(self) -> float | None:
        """Measured, when minimum effort had not brought the hot set below 70 degC by the end of its run: the
        ratio is at least the time watched over thermal-aware's time."""
        ta, me = self.safe_s["thermal_aware"], self.safe_s["minimum_effort"]
        if self.source != "measured" or me is not None or ta is None or ta <= 0.0 or any(self.fell.values()):
            return None
        return self.watched_s / ta

    @property
    def ratio(self) -> float | None:
        ta, me = self.safe_s["thermal_aware"], self.safe_s["minimum_effort"]
        if any(self.fell.values()) or ta is None or ta <= 0.0:
            return None
        # first order: minimum effort holds the hot set above 70 degC for ever; measured: not in time
        if me is None:
            return float("inf") if self.source == "first order" else None
        return me / ta

    def to_json(self) -> dict:
        return {
            "group": self.group,
            "depth_rad": self.depth_rad,
            "source": self.source,
            "ratio": self.ratio,
            "ratio_at_least": self.ratio_at_least,
            "hot_set_safe_s": self.safe_s,
            "modes": self.modes,
            "fell": self.fell,
            "warning_at_s": self.warning_at_s,
            "watched_after_warning_s": self.watched_s,
        }


def predict_cell(group: str, depth_rad: float, body: WholeBody | None = None,
                 time_to_warning_s: float = 100.0) -> Cell:
    """The first-order prediction of a cell (module docstring)."""
    body = body or WholeBody()
    sc = map_scenario(group, depth_rad, body, time_to_warning_s)
    bank = datasheet_bank(VALKYRIE, AMBIENT_C, scenario=sc)
    q_double = standing(body, crouch_angles(depth_rad))
    q_single = single_support(body, q_double, HEAT_SIDE)
    steady = bank.equilibrium_C(body.statics(q_single, HEAT_SIDE).efforts)
    t = np.arange(0.0, 1200.0, 0.1)
    heating = steady[None, :] + (AMBIENT_C - steady[None, :]) * np.exp(-t[:, None] / bank.RC_s[None, :])
    reached = np.flatnonzero(heating.max(axis=1) >= LIMITS.warning_C)
    if not reached.size:
        return Cell(group, depth_rad, "first order", dict.fromkeys(STRATEGIES), {},
                    dict.fromkeys(STRATEGIES, False), None)
    at_warning = heating[reached[0]]
    watched = np.array([ACTUATORS.index(a) for a in hot_set(group)])
    safe, modes = {}, {}
    for strategy, objective in (("thermal_aware", "thermal"), ("minimum_effort", "effort")):
        plan = ContactModePlanner(body, objective).plan(q_double, bank, at_warning)
        held = plan.results[plan.mode]
        steady_after = bank.equilibrium_C(body.efforts(held.q, held.torques_Nm))
        times = first_order_cooling_s(at_warning[watched], LIMITS.recovered_C, steady_after[watched],
                                      bank.RC_s[watched])
        times = np.where(at_warning[watched] <= LIMITS.recovered_C, 0.0, times)
        safe[strategy] = float(times.max()) if np.isfinite(times.max()) else None
        modes[strategy] = [plan.mode]
    return Cell(group, depth_rad, "first order", safe, modes, dict.fromkeys(STRATEGIES, False),
                float(t[reached[0]]))


def measure_cell(group: str, depth_rad: float, seed: int = 0, time_to_warning_s: float = 100.0,
                 max_heat_s: float | None = None, max_recovery_s: float = 120.0, quiet: bool = True) -> Cell:
    """The cell in PyBullet: both strategies from the same warning state (the same seed and heating).  A run
    lasts ``max_heat_s`` (default: 1.5 times the time to the warning, plus 30 s) and ``max_recovery_s`` in
    all."""
    max_heat_s = 1.5 * time_to_warning_s + 30.0 if max_heat_s is None else max_heat_s
    sc = map_scenario(group, depth_rad, time_to_warning_s=time_to_warning_s)
    bank = datasheet_bank(VALKYRIE, AMBIENT_C, scenario=sc)
    watched = [ACTUATORS.index(a) for a in hot_set(group)]
    safe, modes, fell, warning, seen = {}, {}, {}, None, None
    for strategy in STRATEGIES:
        run = run_recovery(strategy, bank, seed=seed, heat_side=HEAT_SIDE, max_heat_s=max_heat_s,
                           max_recovery_s=max_recovery_s, quiet=quiet, scenario=sc)
        safe[strategy] = run.safe_after_warning(watched)
        modes[strategy] = [m for _, m in run.decisions]
        fell[strategy] = run.fell
        warning = run.warning_at_s
        seen = None if warning is None else run.time_s[-1] - warning
    return Cell(group, depth_rad, "measured", safe, modes, fell, warning, seen)


def agreeing_groups(measured: list[Cell], predicted: dict) -> dict[str, bool]:
    """Per group: whether every measured cell's ratio is within ``AGREEMENT`` of the prediction for that cell
    (a cell where minimum effort was not safe by the end of its run agrees with a prediction at least as large
    as its bound; a fall disagrees)."""
    out = {}
    for group in {c.group for c in measured}:
        ok = True
        for c in (c for c in measured if c.group == group):
            p = predicted[(group, c.depth_rad)].ratio
            # minimum effort not safe by the end: the prediction must say so too
            if c.ratio_at_least is not None:
                ok &= p is not None and p >= c.ratio_at_least
            else:
                ok &= c.ratio is not None and p is not None and abs(p - c.ratio) <= AGREEMENT * c.ratio
        out[group] = bool(ok)
    return out

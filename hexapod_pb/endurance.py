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
calibration log (:func:`calibrate`), never with the plant's network:

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

from __future__ import annotations

from dataclasses import dataclass, replace
from itertools import product

import numpy as np

from thermolimb.identification.bank import identify_bank
from thermolimb.logs import ThermalLog
from thermolimb.model import FirstOrderBank
from thermolimb.plant import (
    ACTUATOR_SPECS,
    CopperTempco,
    PlantEffects,
    Quantisation,
    SensorNoise,
    ThermalProtection,
)
from thermolimb.plant.periodic import CycleMap

from . import cpg
from .constants import ACTUATOR_MODEL, JOINT_KINDS, JOINTS, LEGS
from .controller import ControllerState, Gains, ThermalContext, control_step
from .params import DAISY, FALLEN_BODY_HEIGHT_M, DaisyParams
from .sim import HexapodSim, SimConfig

MODES = ("walk", "stand")
STRATEGIES = ("vertical_only", "minimax", "minimax_lex", "thermal_aware", "thermal_gait")
THERMAL_STRATEGIES = ("thermal_aware", "thermal_gait")
# copper's temperature coefficient is physics with a known value; the plant's speed losses are sized by choice,
# and on PyBullet's joint speeds (touch-down spikes) they make within-stride bursts no X8 datasheet supports
EFFECTS = PlantEffects(winding_tempco=CopperTempco(), sensor_noise=SensorNoise(), quantisation=Quantisation())
# the measured thermistor cannot lead the winding, so protection on it never starts before the propagated crossing
PROTECTION = ThermalProtection(estimator="measured")
SETTLE_S = 0.5
WARMUP_STRIDES = 3
CYCLE_STRIDES = 8
MAX_YAW_DRIFT_DEG_PER_MIN = 5.0  # a gait turning faster than this by itself is not periodic (measured: <= 0.3 to 25 kg)
MIN_RISE_K = 0.5  # a joint whose log shows less mean Joule rise (five sensor steps) is not identified: prior
WINDING_RC_S = 1.0  # an X8 winding's own time constant is 1.4 s: the fastest an identified RC may be
MIN_SPEED_SHARE = 0.8  # a planned gait keeps at least this share of the nominal gait's measured speed


@dataclass(frozen=True)
class Gait:
    """What the planner may change: duty factor, foot reach from the shoulder (m), body height (m), and the share
    of the time spent standing still (a pause after every eight strides)."""

    duty_factor: float = cpg.CPGParams().duty_factor
    foot_reach_m: float = DAISY.nominal_foot_reach_m
    body_height_m: float = DAISY.nominal_body_height_m
    pause_share: float = 0.0

    def __post_init__(self):
        if not 0.0 <= self.pause_share < 1.0:
            raise ValueError(f"pause_share is a share of the time in [0, 1), got {self.pause_share}")

    def params(self, base: DaisyParams = DAISY) -> DaisyParams:
        return replace(base, nominal_foot_reach_m=self.foot_reach_m, nominal_body_height_m=self.body_height_m)

    def cpg(self) -> cpg.CPGParams:
        """The CPG at this duty factor, its step lengthened to keep the nominal gait's planned speed."""
        nominal = cpg.CPGParams()
        step = nominal.speed_m_s * self.duty_factor * nominal.period_s
        return replace(nominal, duty_factor=self.duty_factor, step_length_m=step)


NOMINAL_GAIT = Gait()
GAIT_CHOICES = {"duty_factor": (0.55, 0.75), "foot_reach_m": (0.16, 0.19, 0.22), "body_height_m": (0.13, 0.16),
                "pause_share": (0.0, 0.1, 0.2)}


@dataclass(frozen=True)
class Cycle:
    """One measured cycle of a periodic duty, and its map on the plant's network."""

    map: CycleMap
    distance_per_s_m: float
    fell: bool
    mean_sq_effort: np.ndarray  # (18,) N^2 m^2 over the cycle
    mean_effort: np.ndarray  # (18,) N m
    yaw_drift_deg: float  # heading change over the cycle: a gait that turns by itself is not periodic


def cycle_steps(gait: Gait, control_hz: float) -> int:
    """Control steps of a cycle's eight strides (its pause not counted)."""
    return int(round(CYCLE_STRIDES * gait.cpg().period_s * control_hz))


def pause_steps(gait: Gait, control_hz: float) -> int:
    """Control steps of the pause that makes ``pause_share`` of a cycle."""
    return int(round(cycle_steps(gait, control_hz) * gait.pause_share / (1.0 - gait.pause_share)))


def _run_duty(sim: HexapodSim, params: DaisyParams, gait: Gait, payload_kg: float, config: SimConfig, walking: bool,
              forces: str, thermal: ThermalContext | None, steps: int):
    """Settle, warm up for a few strides, then run ``steps`` control steps; yield ``(k, reading)`` after each step.

    ``k`` counts from the end of the warm-up: -1 is the last warm-up step,
    0 the first recorded one.  A stance no solver can meet raises
    ``RuntimeError`` (the legs cannot hold the load).
    """
    gait_params = gait.cpg()
    control = ControllerState(cpg.initial_state(None, gait_params))
    reading = sim.read()
    settle = int(SETTLE_S * config.control_hz)
    warmup = settle + cycle_steps(gait, config.control_hz) // CYCLE_STRIDES * WARMUP_STRIDES
    for k in range(warmup + steps):
        tau, control, _ = control_step(reading, control, params, gait_params, forces, config.control_dt_s,
                                       payload_kg, Gains(), thermal, walking=walking and k >= settle)
        reading = sim.step(tau)
        yield k - warmup, reading


def measure_cycle(payload_kg: float, mode: str, forces: str, ambient_C: float, gait: Gait = NOMINAL_GAIT,
                  state: np.ndarray | None = None, thermal: ThermalContext | None = None, seed: int = 0) -> Cycle:
    """Run the robot until its duty is periodic and record one cycle; the plant starts in ``state`` (or at ambient).

    Walking with a pause, the pause is measured standing from the state the
    strides leave, and joined to their cycle.
    """
    if mode not in MODES:
        raise ValueError(f"unknown mode {mode!r}; expected one of {', '.join(MODES)}")
    moving = replace(gait, pause_share=0.0)
    hz = SimConfig().control_hz
    strides = _record(payload_kg, mode == "walk", forces, ambient_C, moving, state, thermal, seed,
                      cycle_steps(moving, hz))
    if mode == "stand" or pause_steps(gait, hz) == 0 or strides.fell:
        return strides
    start = np.full(strides.map.M.shape[0], float(ambient_C)) if state is None else state
    pause = _record(payload_kg, False, forces, ambient_C, moving, strides.map.M @ start + strides.map.c, thermal,
                    seed, pause_steps(gait, hz))
    if pause.fell:
        return pause
    joined = strides.map.followed_by(pause.map)
    mean_sq, mean = _with_pause(strides, pause, pause.map.steps / joined.steps)
    return Cycle(joined, strides.distance_per_s_m * strides.map.period_s / joined.period_s, False, mean_sq, mean,
                 strides.yaw_drift_deg)


def _with_pause(cycle: Cycle, pause: Cycle | None, share: float) -> tuple[np.ndarray, np.ndarray]:
    """A cycle's mean squared and mean effort with ``share`` of the time spent in ``pause`` (if any)."""
    if pause is None:
        return cycle.mean_sq_effort, cycle.mean_effort
    return ((1 - share) * cycle.mean_sq_effort + share * pause.mean_sq_effort,
            (1 - share) * cycle.mean_effort + share * pause.mean_effort)


def _record(payload_kg: float, walking: bool, forces: str, ambient_C: float, gait: Gait, state: np.ndarray | None,
            thermal: ThermalContext | None, seed: int, steps: int) -> Cycle:
    """Settle and warm up, then record ``steps`` control steps of walking (or standing) as a cycle."""
    config = SimConfig(payload_kg=payload_kg, ambient_C=ambient_C)
    params = gait.params()
    efforts, velocities = np.zeros((steps, len(JOINTS))), np.zeros((steps, len(JOINTS)))
    with HexapodSim(params=params, config=config, plant_effects=EFFECTS, seed=seed, protection=PROTECTION) as sim:
        if state is not None:
            sim.plant.set_state(state)
        start, start_yaw, fell = sim.read().body_position_m.copy(), 0.0, False
        reading = None
        try:
            for k, reading in _run_duty(sim, params, gait, payload_kg, config, walking, forces, thermal, steps):
                if reading.body_position_m[2] < FALLEN_BODY_HEIGHT_M:
                    fell = True
                    break
                if k == -1:
                    start, start_yaw = reading.body_position_m.copy(), _yaw_deg(reading.world_R_body)
                elif k >= 0:
                    efforts[k], velocities[k] = sim.applied_Nm, reading.qd_rad_s
        except RuntimeError:  # a stance problem no solver can meet: the legs cannot hold this load
            fell = True
        if fell:
            efforts[:], velocities[:] = 0.0, 0.0
        if fell or not walking:
            distance = 0.0  # standing goes nowhere by definition (the body's drift is not distance)
        else:
            distance = float(reading.body_position_m[0] - start[0])
        drift = 0.0 if fell else abs(_wrapped_deg(_yaw_deg(reading.world_R_body) - start_yaw))
        cycle_map = CycleMap(sim.plant, efforts, velocities, config.control_dt_s)
    return Cycle(cycle_map, distance / cycle_map.period_s, fell, (efforts**2).mean(axis=0), efforts.mean(axis=0),
                 drift)


def _yaw_deg(world_R_body: np.ndarray) -> float:
    return float(np.degrees(np.arctan2(world_R_body[1, 0], world_R_body[0, 0])))


def _wrapped_deg(angle_deg: float) -> float:
    """An angle difference in [-180, 180) degrees: a heading crossing +-180 has not turned a full circle."""
    return (angle_deg + 180.0) % 360.0 - 180.0


# ------------------------------------------------------------------ models
def calibrate(duration_s: float, payload_kg: float = 20.0, seed: int = 0) -> tuple[FirstOrderBank, ThermalLog, float]:
    """The robot's own log: walking then standing with ``payload_kg`` at 25 degC; Eq. 5 identified from it.

    Returns the bank (JOINTS order), the log and the ambient the robot
    measured when it started cold (its thermistors' mean first reading).
    """
    gait = cpg.CPGParams()
    config = SimConfig(payload_kg=payload_kg, ambient_C=25.0)
    with HexapodSim(config=config, plant_effects=EFFECTS, seed=seed, protection=PROTECTION) as sim:
        reading = sim.read()
        measured_ambient = float(np.mean(reading.temperature_C))
        control = ControllerState(cpg.initial_state(None, gait))
        n = int(round(duration_s * config.control_hz))
        for k in range(n):
            # walk, stand, walk, stand: efforts that change, so every walking joint is identifiable
            walking = (4 * k // n) % 2 == 0
            tau, control, _ = control_step(reading, control, DAISY, gait, "vertical_only", config.control_dt_s,
                                           payload_kg, Gains(), None, walking=walking)
            reading = sim.step(tau)
        log = sim.thermal_log()
    # joule only: the X8 has no series-elastic bias to find, and a shoulder's torque never changes sign, so an
    # effort_bias term trades off against betaR on this log and extrapolates wildly
    bank = identify_bank(log, JOINTS, DAISY.effort_limit_Nm, min_rc_s=WINDING_RC_S, model="joule",
                         min_rise_K=MIN_RISE_K)
    return bank, log, measured_ambient


def at_ambient(bank: FirstOrderBank, ambient_C: float) -> FirstOrderBank:
    """The identified bank planning hours ahead at ``ambient_C``: every offset is the ambient the robot measures cold.

    Fitted on minutes of log, Eq. 5's offset holds whatever the first-order
    model could not follow -- here the housing's and body's warming, more
    for busy joints than idle ones -- and a minimax over predicted
    temperatures would shift load onto the joints the offsets call cool.
    Hours ahead the offset is the ambient.
    """
    return replace(bank, T_offset_C=np.full(bank.n, float(ambient_C)))


def predicted_peak_C(bank: FirstOrderBank, cycle: Cycle, pause: Cycle | None = None, pause_share: float = 0.0) -> float:
    """The hottest equilibrium the identified models predict for a cycle's mean heating (degC), with ``pause_share``
    of the time spent in the ``pause`` cycle."""
    mean_sq, mean = _with_pause(cycle, pause, pause_share)
    return float(np.max(bank.betaR_K_per_effort2 * mean_sq - bank.beta_biasR_K_per_effort * mean + bank.T_offset_C))


@dataclass(frozen=True)
class GaitPlan:
    gait: Gait
    predicted_peak_C: float
    nominal_predicted_peak_C: float
    distance_per_s_m: float
    nominal_distance_per_s_m: float
    candidates: int


def plan_gait(payload_kg: float, mode: str, ambient_C: float, bank: FirstOrderBank, seed: int = 0,
              choices: dict[str, tuple[float, ...]] = GAIT_CHOICES) -> GaitPlan:
    """The gait whose measured torques the identified models say run coolest, at >= 80 % of the stock speed.

    Standing, only the reach and height change (the duty factor and pauses
    do not exist).  A pause's standing duty is measured once per reach and
    height and weighed in by its share of the time.
    """
    thermal = ThermalContext(bank)
    nominal = measure_cycle(payload_kg, mode, "thermal_aware", ambient_C, NOMINAL_GAIT, thermal=thermal, seed=seed)
    stock = measure_cycle(payload_kg, mode, "vertical_only", ambient_C, NOMINAL_GAIT, seed=seed)
    # the speed to keep is the stock controller's (vertical forces on the nominal gait), or this one's if faster
    reference = max(nominal.distance_per_s_m, stock.distance_per_s_m)
    walking = mode == "walk"
    duties = choices["duty_factor"] if walking else (NOMINAL_GAIT.duty_factor,)
    pauses = choices.get("pause_share", (0.0,)) if walking else (0.0,)
    best = (predicted_peak_C(bank, nominal) if not nominal.fell else np.inf, NOMINAL_GAIT, nominal.distance_per_s_m)
    count, standing = 1, {}
    for duty, reach, height in product(duties, choices["foot_reach_m"], choices["body_height_m"]):
        gait = Gait(duty, reach, height)
        if gait == NOMINAL_GAIT:
            cycle = nominal
        else:
            cycle = measure_cycle(payload_kg, mode, "thermal_aware", ambient_C, gait, thermal=thermal, seed=seed)
            count += 1
        if cycle.fell:
            continue
        for share in pauses:
            distance = (1 - share) * cycle.distance_per_s_m
            if (share == 0.0 and gait == NOMINAL_GAIT) or distance < MIN_SPEED_SHARE * reference:
                continue
            pause = None
            if share > 0.0:
                if (reach, height) not in standing:
                    standing[reach, height] = measure_cycle(payload_kg, "stand", "thermal_aware", ambient_C, gait,
                                                            thermal=thermal, seed=seed)
                pause = standing[reach, height]
                count += 1
                if pause.fell:
                    continue
            peak = predicted_peak_C(bank, cycle, pause, share)
            if peak < best[0]:
                best = (peak, replace(gait, pause_share=share), distance)
    return GaitPlan(best[1], float(best[0]), predicted_peak_C(bank, nominal), best[2], reference, count)


# ------------------------------------------------------------------ cells
@dataclass(frozen=True)
class CellResult:
    payload_kg: float
    ambient_C: float
    mode: str
    strategy: str
    time_to_derate_s: float | None
    horizon_s: float
    distance_per_s_m: float
    fell: bool
    hottest: str  # the actuator that derates first, or the hottest at the horizon
    hottest_C: float  # its winding when derating starts, or at the horizon
    steady_hottest_C: float | None  # the hottest winding of the last measured cycle repeated forever
    yaw_drift_deg_per_min: float  # the largest heading drift measured: above a few degrees the gait is not periodic
    windows: int
    gait: Gait

    @property
    def holds_heading(self) -> bool:
        return self.yaw_drift_deg_per_min <= MAX_YAW_DRIFT_DEG_PER_MIN

    def row(self) -> dict:
        return {"payload_kg": self.payload_kg, "ambient_C": self.ambient_C, "mode": self.mode,
                "strategy": self.strategy, "time_to_derate_s": self.time_to_derate_s, "horizon_s": self.horizon_s,
                "distance_per_s_m": self.distance_per_s_m, "fell": self.fell, "hottest": self.hottest,
                "hottest_C": self.hottest_C, "steady_hottest_C": self.steady_hottest_C,
                "yaw_drift_deg_per_min": self.yaw_drift_deg_per_min,
                "holds_heading": self.holds_heading, "windows": self.windows, "duty_factor": self.gait.duty_factor,
                "foot_reach_m": self.gait.foot_reach_m, "body_height_m": self.gait.body_height_m,
                "pause_share": self.gait.pause_share}


def derating_threshold_C() -> np.ndarray:
    """Winding temperature (degC) at which each actuator's protection starts to derate."""
    limits = np.array([ACTUATOR_SPECS[ACTUATOR_MODEL[k]].winding_limit_C for _ in LEGS for k in JOINT_KINDS])
    return limits - PROTECTION.margin_K


def endurance(payload_kg: float, ambient_C: float, mode: str, strategy: str, horizon_s: float,
              bank: FirstOrderBank | None = None, window_s: float = 1800.0, gait: Gait | None = None,
              seed: int = 0, choices: dict[str, tuple[float, ...]] = GAIT_CHOICES) -> CellResult:
    """Time until the first actuator derates (``None`` if not within ``horizon_s``), from cold at ``ambient_C``.

    ``bank`` (identified, :func:`at_ambient` this ambient) is needed by the
    thermal-aware strategies; ``gait`` skips ``thermal_gait``'s planning
    (``choices`` are the gaits it plans among).
    """
    if strategy not in STRATEGIES:
        raise ValueError(f"unknown strategy {strategy!r}; expected one of {', '.join(STRATEGIES)}")
    thermal = None
    if strategy in THERMAL_STRATEGIES:
        if bank is None:
            raise ValueError(f"the {strategy} strategy needs models identified from the robot's log (bank=)")
        thermal = ThermalContext(bank)
    if gait is None:
        gait = plan_gait(payload_kg, mode, ambient_C, bank, seed, choices).gait if strategy == "thermal_gait" else NOMINAL_GAIT
    forces = "thermal_aware" if strategy in THERMAL_STRATEGIES else strategy
    window = window_s if thermal is not None else horizon_s
    threshold = derating_threshold_C()
    state, elapsed, windows = None, 0.0, 0
    distances, fell, crossing, winding, steady, drift = [], False, None, None, None, 0.0
    while elapsed < horizon_s - 1e-9:
        cycle = measure_cycle(payload_kg, mode, forces, ambient_C, gait, state, thermal, seed)
        windows += 1
        if cycle.fell:  # the robot cannot do this duty at all: nothing to propagate
            fell = True
            winding = winding or ("", float(ambient_C))
            break
        distances.append(cycle.distance_per_s_m)
        steady = float(cycle.map.steady_peak_C().max())
        drift = max(drift, cycle.yaw_drift_deg / cycle.map.period_s * 60.0)
        if state is None:
            state = np.full(cycle.map.M.shape[0], ambient_C)
        span = min(window, horizon_s - elapsed)
        prop = cycle.map.propagate(state, span, threshold)
        if prop.crossing is not None:
            crossing = elapsed + prop.crossing.time_s
            j = prop.crossing.actuator
            winding = (JOINTS[j], float(prop.peak_winding_C[-1, j]))
            break
        state = prop.final_state
        elapsed += len(prop.cycle_start_s) * cycle.map.period_s
        w = state[cycle.map.winding_index]
        winding = (JOINTS[int(np.argmax(w))], float(np.max(w)))
    return CellResult(float(payload_kg), float(ambient_C), mode, strategy, crossing, float(horizon_s),
                      0.0 if fell else float(np.mean(distances)), fell, winding[0], winding[1], steady, drift, windows, gait)


# ------------------------------------------------------------------ the shortcut checked
@dataclass(frozen=True)
class PeriodicCheck:
    """The propagated cell against the whole run in PyBullet: the hottest actuator's true winding, averaged over
    each cycle (a cycle's start falls at a slightly different phase of the stride as the run goes on, and the
    winding swings by kelvins within a stride)."""

    duration_s: float
    cycle_start_s: np.ndarray
    pybullet_hottest_C: np.ndarray  # hottest cycle-mean true winding, full PyBullet run
    propagated_hottest_C: np.ndarray  # the same from one measured cycle, propagated

    @property
    def max_abs_difference_K(self) -> float:
        return float(np.max(np.abs(self.pybullet_hottest_C - self.propagated_hottest_C)))

    @property
    def final_difference_K(self) -> float:
        return float(self.propagated_hottest_C[-1] - self.pybullet_hottest_C[-1])

    def summary(self) -> dict:
        return {"duration_s": self.duration_s, "max_abs_difference_K": self.max_abs_difference_K,
                "final_difference_K": self.final_difference_K,
                "final_pybullet_C": float(self.pybullet_hottest_C[-1]),
                "final_propagated_C": float(self.propagated_hottest_C[-1])}


def check_periodic(payload_kg: float, ambient_C: float, mode: str, strategy: str, duration_s: float,
                   seed: int = 0) -> PeriodicCheck:
    """Run a temperature-independent strategy in PyBullet for ``duration_s`` and propagate its first cycle as long.

    Both start from cold and settle and warm up alike; the full run keeps
    going with the thermal plant stepped every control period.
    """
    if strategy in THERMAL_STRATEGIES:
        raise ValueError("check a strategy whose torques do not depend on the temperatures (one cycle propagated)")
    cycle = measure_cycle(payload_kg, mode, strategy, ambient_C, seed=seed)
    if cycle.fell:
        raise ValueError(f"the robot cannot {mode} with {payload_kg} kg under {strategy}: nothing to check")
    steps = cycle.map.steps
    config = SimConfig(payload_kg=payload_kg, ambient_C=ambient_C)
    cycles = int(np.ceil(duration_s / cycle.map.period_s))
    hottest = np.empty(cycles)
    start = None
    with HexapodSim(config=config, plant_effects=EFFECTS, seed=seed, protection=PROTECTION) as sim:
        total = np.zeros(len(JOINTS))
        for k, _ in _run_duty(sim, DAISY, NOMINAL_GAIT, payload_kg, config, mode == "walk", strategy, None,
                              cycles * steps):
            if k == -1:
                start = sim.plant.state
            elif k >= 0:
                total += sim.plant.winding_C
                if (k + 1) % steps == 0:
                    hottest[k // steps] = total.max() / steps
                    total[:] = 0.0
    prop = cycle.map.propagate(start, cycles * cycle.map.period_s)
    return PeriodicCheck(cycles * cycle.map.period_s, prop.cycle_start_s, hottest, prop.mean_winding_C.max(axis=1))

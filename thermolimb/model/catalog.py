"""The built-in catalog of model terms (the names ``--model`` accepts).

Each term states the physics it stands for, its parameters with units and
bounds, and the log columns it needs.  The plant (``thermolimb.plant``) has a
physical counterpart for each, so that logs with a hidden effect exist to test
the diagnosis.  Parameters are expressed as steady-state temperature rises,
like Jorgensen et al.'s ``beta*R``: ``rise = R * heat``.
"""

from __future__ import annotations

import numpy as np

from ..constants import COPPER_REFERENCE_C
from ..util.numbers import significant
from .scan import first_order_scan
from .signals import Signals
from .terms import Parameter, Term, register_term

AMBIENT_REFERENCE_C = 25.0  # T_offset is the offset at this logged ambient when ambient_variation is on


def _speed(s: Signals) -> np.ndarray:
    return np.abs(s.channel("velocity"))


class LinearTerm(Term):
    """A term whose rise is its one parameter times a regressor built from the log (linear in that parameter)."""

    def regressor(self, s: Signals) -> np.ndarray:
        raise NotImplementedError  # abstract

    def contribution(self, p, s):
        return p[self.parameters[0].name] * self.regressor(s), 0.0

    def features(self, s, temperature_C):
        return self.regressor(s)[:, None]


@register_term
class Joule(LinearTerm):
    """Effort-squared heating: Jorgensen et al.'s ``beta*R*F^2`` (Eq. 5)."""

    name = "joule"
    label = "Joule heating from effort"
    description = "Joule heating from effort squared (the base heat source)"
    parameters = (
        Parameter("betaR_K_per_effort2", "K/({effort})^2", 0.0, np.inf, 0.1,
                  "steady-state rise per squared effort, beta*R of Eq. 5",
                  "effort held at three or more distinct levels"),
    )
    is_heat_source = True

    def regressor(self, s):
        return s.effort**2


@register_term
class EffortBias(LinearTerm):
    """Linear effort term from a series-elastic effort bias: ``-beta_bias*R*F`` (Eq. 5)."""

    name = "effort_bias"
    label = "effort bias"
    description = "linear effort term (series-elastic bias of the torque-current map)"
    parameters = (
        Parameter("beta_biasR_K_per_effort", "K/({effort})", -np.inf, np.inf, 0.1,
                  "beta_bias*R of Eq. 5; positive when the bias lowers heating at positive effort",
                  "effort held at three or more distinct levels, ideally of both signs"),
    )

    def regressor(self, s):
        return -s.effort


@register_term
class CurrentHeating(LinearTerm):
    """Joule heat from the measured current, which also sees current that makes no torque."""

    name = "current_heating"
    label = "Joule heating from current"
    description = "Joule heating from measured current squared"
    parameters = (
        Parameter("currentR_K_per_A2", "K/({current})^2", 0.0, np.inf, 0.01,
                  "steady-state rise per squared ampere (R_e * R_thermal)",
                  "current at three or more distinct levels"),
    )
    columns = ("current",)
    is_heat_source = True

    def regressor(self, s):
        return s.channel("current") ** 2


@register_term
class PowerHeating(LinearTerm):
    """Heat in proportion to measured electrical input power (benches that log power, not torque)."""

    name = "power_heating"
    label = "heating from electrical power"
    description = "heating in proportion to electrical input power (its losses are a share of it)"
    parameters = (
        Parameter("powerR_K_per_W", "K/({power})", 0.0, np.inf, 0.1,
                  "steady-state rise per watt of input power (loss share times thermal resistance)",
                  "power at three or more distinct levels"),
    )
    columns = ("power",)
    is_heat_source = True

    def regressor(self, s):
        return s.channel("power")


@register_term
class HousingBoundary(LinearTerm):
    """The winding loses heat to its measured housing: ``g T_housing`` replaces most of the constant offset.

    With a second sensor on the housing (case, stator body, driver board) the
    slow thermal masses need not be modelled: their temperature is measured.
    ``T_offset`` then holds what the housing does not explain (``(1 - g)`` of ambient).
    """

    name = "housing_boundary"
    label = "housing as the boundary"
    description = "the winding's boundary is the measured housing temperature (a second sensor)"
    parameters = (
        Parameter("housing_gain", "1", 0.0, 1.5, 0.9,
                  "kelvin of winding equilibrium per kelvin of housing (1: all heat leaves through the housing)",
                  "a housing temperature that moves during the log", plausible=(0.3, 1.2)),
    )
    columns = ("housing",)

    def regressor(self, s):
        return s.channel("housing")


@register_term
class WindingTempco(Term):
    """Copper resistance rising with temperature: the Joule terms times ``1 + alpha (T - 25 degC)``."""

    name = "winding_tempco"
    label = "copper's temperature coefficient"
    description = "copper resistance rising with winding temperature"
    parameters = (
        Parameter("alpha_per_K", "1/K", -0.01, 0.02, 0.004,
                  "temperature coefficient of the winding resistance (copper: about 0.0039/K)",
                  "hot and cool phases at the same effort", plausible=(0.002, 0.006)),
    )

    def contribution(self, p, s):
        joule = 0.0
        if "betaR_K_per_effort2" in p:
            joule = joule + p["betaR_K_per_effort2"] * s.effort**2
        if "currentR_K_per_A2" in p and s.current_A is not None:
            joule = joule + p["currentR_K_per_A2"] * s.current_A**2
        alpha = p["alpha_per_K"]
        return -alpha * COPPER_REFERENCE_C * joule, alpha * joule


@register_term
class SpeedLosses(Term):
    """Friction and iron losses that grow with speed: ``k1 |v| + k2 v^2``."""

    name = "speed_losses"
    label = "speed losses"
    description = "friction and iron losses growing with speed"
    parameters = (
        Parameter("speed_K_per_rad_s", "K/({velocity})", 0.0, np.inf, 1.0,
                  "rise per unit speed (friction)", "motion at several speeds"),
        Parameter("speed2_K_per_rad2_s2", "K/({velocity})^2", 0.0, np.inf, 0.5,
                  "rise per squared speed (iron losses)", "motion at several speeds"),
    )
    columns = ("velocity",)

    def contribution(self, p, s):
        v = _speed(s)
        return p["speed_K_per_rad_s"] * v + p["speed2_K_per_rad2_s2"] * v**2, 0.0

    def features(self, s, temperature_C):
        v = _speed(s)
        return np.column_stack([v, v**2])


@register_term
class NeighborCoupling(Term):
    """Heat conducted from neighbouring actuators: ``k (mean T_neighbours - T)``.

    Neighbours are the actuators next to this one in the log's order (a limb
    logged joint by joint), as :meth:`thermolimb.logs.ThermalLog.series` gives them.
    """

    name = "neighbor_coupling"
    label = "heat from neighbours"
    description = "conduction from the other actuators, from their measured temperatures"
    parameters = (
        Parameter("neighbor_ratio", "1", 0.0, 10.0, 0.1,
                  "neighbour conductance over the conductance to ambient",
                  "neighbours whose temperature differs from this actuator's", plausible=(0.0, 5.0)),
    )
    columns = ("neighbors",)

    def contribution(self, p, s):
        k = p["neighbor_ratio"]
        return k * s.neighbor_mean_C, -k

    def features(self, s, temperature_C):
        return (s.neighbor_mean_C - temperature_C)[:, None]


@register_term
class AmbientVariation(LinearTerm):
    """The offset follows the logged ambient (the base model keeps it constant)."""

    name = "ambient_variation"
    label = "ambient variation"
    description = "offset follows the logged ambient temperature"
    parameters = (
        Parameter("ambient_gain", "1", -1.0, 3.0, 1.0,
                  "kelvin of offset per kelvin of logged ambient (1 for a perfect ambient sensor)",
                  "ambient that changes during the log", plausible=(0.5, 1.5)),
    )
    columns = ("ambient",)
    boundary = True

    def regressor(self, s):
        return s.channel("ambient") - AMBIENT_REFERENCE_C


HOUSING_AIRFLOW = "housing_cooling_per_rad_s"


def _airflow_parameter(name: str, conductance: str, when: str) -> Parameter:
    """The gain of airflow on a conductance to ambient: it times ``1 + gain |v|``."""
    return Parameter(name, "1/({velocity})", 0.0, 20.0, 0.3, f"relative increase of {conductance} per unit speed",
                     f"motion at several speeds while {when}", plausible=(0.0, 5.0))


@register_term
class MotionCooling(Term):
    """Cooling improves with speed: the loss to ambient times ``1 + h |v|``."""

    name = "motion_cooling"
    label = "cooling by motion"
    description = "cooling that improves with speed (airflow)"
    parameters = (_airflow_parameter("cooling_per_rad_s", "the conductance to ambient", "warm"),)
    columns = ("velocity",)

    def contribution(self, p, s):
        h = p["cooling_per_rad_s"] * _speed(s)
        return h * p["T_offset_C"], -h


class SlowMass(Term):
    """A slower thermal mass between the winding and ambient, as one cascade stage.

    The slow node settles to ``T_offset + phi (u - T_offset)`` with time
    constant ``tau`` (``u``: the equilibrium the other terms give); the
    winding settles to that node plus the remaining ``(1 - phi)`` of the rise
    (a cascade: the steady state is unchanged).  Stages stack: a third mass
    reshapes what the second leaves.
    """

    fraction: str
    tau: str
    carries_state = True  # its node's temperature carries over between pieces of a run (ThermalModel.simulate)

    def implausible(self, p):
        if p[self.tau] <= p["RC_s"]:
            return (f"{self.tau} = {significant(p[self.tau], 3)} s is not slower than the winding's "
                    f"RC_s = {significant(p['RC_s'], 3)} s fitted with it")
        return super().implausible(p)

    def winding_share(self, p):
        return 1.0 - p[self.fraction]

    def airflow(self, p, s) -> np.ndarray | float:
        """How many times its still-air conductance to ambient this mass has (1: none moves it)."""
        return 1.0

    def shape_equilibrium(self, p, s, equilibrium_C, initial_C, boundary_C, state=None):
        phi = p[self.fraction]
        if phi == 0.0:
            self.state = None
            return equilibrium_C
        # the heat's rise above the boundary builds up phi across this mass; the boundary itself (ambient)
        # reaches the winding only through it; airflow divides this mass's rise and its time constant alike
        heat = equilibrium_C - boundary_C
        flow = self.airflow(p, s)
        target = boundary_C + phi * heat / flow
        a = np.exp(-s.interval_s * (flow[:-1] if np.ndim(flow) else flow) / p[self.tau])
        # the slow mass starts in proportion, as if the initial temperature were a steady state, unless it
        # carries on from where an earlier piece of the run left it
        start = boundary_C[0] + phi * (initial_C - boundary_C[0]) if state is None else state
        frame = first_order_scan(a, (1.0 - a) * target[:-1], start)
        self.state = float(frame[-1])
        return frame + (1.0 - phi) * heat


def _slow_mass_parameters(fraction: str, tau: str, which: str) -> tuple[Parameter, Parameter]:
    return (
        Parameter(fraction, "1", 0.0, 0.98, 0.5,
                  f"share of the steady-state rise that builds up across the {which} mass",
                  "long heating or cooling phases (several slow time constants)", plausible=(0.05, 0.95)),
        Parameter(tau, "s", 1.0, 1e6, 2000.0, f"time constant of the {which} mass",
                  "long heating or cooling phases (several slow time constants)", null=2000.0, nuisance=True),
    )


@register_term
class SecondNode(SlowMass):
    """A second, slower thermal mass (a housing or frame) between the winding and ambient."""

    name = "second_node"
    label = "a second thermal mass"
    description = "a second, slower thermal mass"
    fraction, tau = "frame_fraction", "frame_tau_s"
    parameters = _slow_mass_parameters(fraction, tau, "slow")

    def airflow(self, p, s):
        h = p.get(HOUSING_AIRFLOW, 0.0)  # set by housing_motion_cooling, when the model has it
        return 1.0 + h * _speed(s) if h else 1.0


@register_term
class HousingMotionCooling(Term):
    """Airflow while moving cools the slow mass (the housing), not the winding: the second mass's conductance
    to ambient times ``1 + h |v|``, which shrinks its share of the rise and its time constant alike."""

    name = "housing_motion_cooling"
    label = "the housing cooled by motion"
    description = "cooling of the housing (the second mass) that improves with speed (airflow)"
    parameters = (_airflow_parameter(HOUSING_AIRFLOW, "the housing's conductance to ambient", "the housing is warm"),)
    columns = ("velocity",)
    requires = ("second_node",)


@register_term
class ThirdNode(SlowMass):
    """A third thermal mass: actuators whose housing and body both store heat (three time scales)."""

    name = "third_node"
    label = "a third thermal mass"
    description = "a third thermal mass (housing and body both store heat)"
    fraction, tau = "body_fraction", "body_tau_s"
    parameters = _slow_mass_parameters(fraction, tau, "third")
    requires = ("second_node",)


@register_term
class SensorLag(Term):
    """The thermistor lags the winding: ``tau_s dT_s/dt = T - T_s``."""

    name = "sensor_lag"
    label = "sensor lag"
    description = "the thermistor lags the winding"
    parameters = (
        Parameter("sensor_tau_s", "s", 0.0, 600.0, 10.0, "time constant of the thermistor",
                  "fast temperature changes (short heating bursts)", plausible=(0.2, 120.0)),
    )

    def initial_winding(self, p, measured_C, rate_K_per_s):
        return measured_C + p["sensor_tau_s"] * rate_K_per_s  # the lagged reading trails the winding

    def shape_output(self, p, s, winding_C, measured_initial_C):
        tau = p["sensor_tau_s"]
        if tau <= 0.0:
            return winding_C
        dt = s.interval_s
        a = np.exp(-dt / tau)
        # first-order hold: exact when the winding temperature moves linearly between samples
        ramp = 1.0 - tau / dt * (1.0 - a)
        b = (1.0 - a) * winding_C[:-1] + ramp * np.diff(winding_C)
        return first_order_scan(a, b, measured_initial_C)

"""Slower thermal masses between the winding and ambient: a housing or frame, and a body behind it, each a
cascade stage of the model; airflow on the housing.  The plant's X8 network has them of its own (winding,
housing, body): no switch hides them."""

from __future__ import annotations

import numpy as np

from ..model.terms import LONG_TIME_CONSTANT, Parameter, Term, airflow_terms, register_term, terms_in
from ..util.numbers import significant
from .base import SLOW_DRIFT, Effect, Hidden, airflow_parameter, register, speed

HOUSING_AIRFLOW = "housing_cooling_per_rad_s"
MIN_FLOW = 1e-3  # the least share of its still-air conductance a slow mass keeps


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
    # its node's temperature carries over between pieces of a run (ThermalModel.simulate)
    carries_state = True

    def implausible(self, p, units=None):
        if p[self.tau] <= p["RC_s"]:
            return (f"{self.tau} = {significant(p[self.tau], 3)} s is not slower than the winding's "
                    f"RC_s = {significant(p['RC_s'], 3)} s fitted with it")
        return super().implausible(p, units)

    def winding_share(self, p):
        return 1.0 - p[self.fraction]

    def stage(self, p):
        return p[self.fraction], p[self.tau]

    def airflow(self, p, s) -> np.ndarray | float:
        """How many times its still-air conductance to ambient this mass has (1: no term of the model moves
        it)."""
        flow = 1.0
        for term in airflow_terms(self.name, p):
            flow = flow + term.airflow_gain(p, s)
        # a channel beyond the range it was fitted on (another run) may drive 1 + h x below zero: held just
        # above it, as the winding's restoring gain is (the term's implausibility says so)
        return np.maximum(flow, MIN_FLOW) if np.ndim(flow) else max(flow, MIN_FLOW)

    def shape_equilibrium(self, p, s, equilibrium_C, initial_C, boundary_C, state=None, offset=0.0):
        phi = p[self.fraction]
        if phi == 0.0:
            self.state = None
            return equilibrium_C
        # the heat's rise above the boundary builds up phi across this mass; the boundary itself (ambient)
        # reaches the winding only through it; airflow divides this mass's rise and its time constant alike
        heat = equilibrium_C - boundary_C
        flow = self.airflow(p, s)
        target = boundary_C + phi * heat / flow
        recursion = s.recursion(flow / p[self.tau])
        # the slow mass starts in proportion, as if the initial temperature were a steady state (less
        # ``offset``, where the data place it otherwise), unless it carries on from where an earlier piece of
        # the run left it; what the inputs put into the masses at the first sample (friction) is heat, which
        # the proportion leaves out as it leaves out the effort's
        rest = boundary_C[0] - heat_into_masses(p, s)
        start = rest + phi * (initial_C - rest) + offset if state is None else state
        frame = recursion.run((1.0 - recursion.a) * target[:-1], start)
        self.state = float(frame[-1])
        return frame + (1.0 - phi) * heat


def heat_into_masses(p, s) -> float:
    """The rise the model's heats put into its slow masses (friction in the housing) give at the first
    sample."""
    return sum(float(np.ravel(s.contribution(cls(), p)[0])[0]) for cls in terms_in(p) if cls.heats_slow_mass)


def _slow_mass_parameters(fraction: str, tau: str, which: str) -> tuple[Parameter, Parameter]:
    return (
        Parameter(fraction, "1", 0.0, 0.98, 0.5,
                  f"share of the steady-state rise that builds up across the {which} mass",
                  "long heating or cooling phases (several slow time constants)", plausible=(0.05, 0.95)),
        # a mass slower than a few runs shows only the start of its rise, along which its share and time
        # constant trade, and its start, placed per run, turns it into a free offset: a fit keeps it within
        # the runs' reach
        Parameter(tau, "s", 1.0, 1e6, 2000.0, f"time constant of the {which} mass",
                  "long heating or cooling phases (several slow time constants)", null=2000.0, nuisance=True,
                  within_runs=LONG_TIME_CONSTANT),
    )


@register_term
class SecondNode(SlowMass):
    """A second, slower thermal mass (a housing or frame) between the winding and ambient."""

    name = "second_node"
    label = "a second thermal mass"
    description = "a second, slower thermal mass"
    fraction, tau = "frame_fraction", "frame_tau_s"
    parameters = _slow_mass_parameters(fraction, tau, "slow")


@register_term
class HousingMotionCooling(Term):
    """Airflow while moving cools the slow mass (the housing), not the winding: the second mass's conductance
    to ambient times ``1 + h |v|``, which shrinks its share of the rise and its time constant alike."""

    name = "housing_motion_cooling"
    label = "the housing cooled by motion"
    description = "cooling of the housing (the second mass) that improves with speed (airflow)"
    parameters = (
        airflow_parameter(HOUSING_AIRFLOW, "the housing's conductance to ambient", "the housing is warm"),
    )
    columns = ("velocity",)
    requires = ("second_node",)
    airflow_on = "second_node"

    def airflow_gain(self, p, s):
        h = p[HOUSING_AIRFLOW]
        return h * speed(s) if h else 0.0


@register_term
class HousingFriction(Term):
    """Bearing and gear friction heat the housing (the second mass), not the winding: ``k |v|`` of steady rise
    that reaches the winding only through the slow mass, where speed losses' rise builds up partly across the
    winding itself.  Iron losses stay in the winding (``speed_losses``' squared speed)."""

    name = "housing_friction"
    label = "friction heat in the housing"
    description = "friction heat put into the housing (the second mass), reaching the winding through it"
    parameters = (Parameter("housing_speed_K_per_rad_s", "K/({velocity})", 0.0, np.inf, 1.0,
                            "steady rise per unit speed of heat put "
                            "into the housing (bearing and gear friction)",
                            "motion at several speeds, held for a slow time constant"),)
    columns = ("velocity",)
    requires = ("second_node",)
    heats_slow_mass = True
    rise_only = True

    def forms(self, s):
        return (speed(s),)

    def combine(self, p, forms):
        return p["housing_speed_K_per_rad_s"] * forms[0], 0.0


@register_term
class ThirdNode(SlowMass):
    """A third thermal mass: actuators whose housing and body both store heat (three time scales)."""

    name = "third_node"
    label = "a third thermal mass"
    description = "a third thermal mass (housing and body both store heat)"
    fraction, tau = "body_fraction", "body_tau_s"
    parameters = _slow_mass_parameters(fraction, tau, "third")
    requires = ("second_node",)


# nothing switched on hides the slow masses: the X8's own housing and body are them
register(Effect("second_node", SecondNode, residual=SLOW_DRIFT, hidden=Hidden("slow_masses", None)),
         Effect("housing_motion_cooling", HousingMotionCooling, residual="|velocity|", rides="velocity"),
         Effect("housing_friction", HousingFriction, residual="|velocity|", rides="velocity"),
         Effect("third_node", ThirdNode, residual=SLOW_DRIFT))

"""Many models at once, as arrays, so that a whole robot's (or a fleet's) actuators step together (the Gymnasium
wrapper, the monitor) exactly as :meth:`ThermalModel.simulate` steps each.

Two families qualify.  The first-order one: Jorgensen et al.'s Joule heating, an effort bias and copper's
coefficient on one node, whose forcing is a polynomial in the effort.  The cascade one: Joule heating, an effort
bias and speed losses, behind slow masses (a second and a third, each a cascade stage; friction may heat the
second, reaching the winding through the stages as the ambient does) and read through a lagging sensor -- what
``diagnose --auto`` often ends with; its forcing gains nothing from the temperature, so every stage is a
first-order recursion of its own."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..constants import COPPER_REFERENCE_C

FAMILY = frozenset({"joule", "effort_bias", "winding_tempco"})  # one node, forcing polynomial in the effort
CASCADE = frozenset({"joule", "effort_bias", "speed_losses", "second_node", "housing_friction", "third_node",
                     "sensor_lag"})
STAGES = ("second_node", "third_node")


def in_family(model) -> bool:
    return set(model.terms) <= FAMILY


def in_cascade(model) -> bool:
    """Stepped by :meth:`ModelArrays.step`: the cascade's terms, its slow masses in the cascade's order."""
    terms = list(model.terms)
    return set(terms) <= CASCADE and (
        "third_node" not in terms or "second_node" in terms and terms.index("second_node") < terms.index("third_node"))


class ModelArrays:
    """The parameters of models of either family, one entry per model (a parameter a model lacks is its null)."""

    NAMES = (("RC_s", 0.0), ("T_offset_C", 0.0), ("betaR_K_per_effort2", 0.0), ("beta_biasR_K_per_effort", 0.0),
             ("alpha_per_K", 0.0), ("speed_K_per_rad_s", 0.0), ("speed2_K_per_rad2_s2", 0.0), ("frame_fraction", 0.0),
             ("frame_tau_s", 1.0), ("body_fraction", 0.0), ("body_tau_s", 1.0), ("sensor_tau_s", 0.0),
             ("housing_speed_K_per_rad_s", 0.0))

    def __init__(self, models: Sequence = (), rows: np.ndarray | None = None):
        """From the models, or from their :meth:`row` stacked (a caller that steps the same models often keeps
        the rows)."""
        columns = (np.array([self.row(m) for m in models]) if rows is None else rows).T
        (self.rc, self.offset, self.b, self.c, self.alpha, self.k1, self.k2, frame, frame_tau, body, body_tau,
         self.sensor_tau, self.kh) = columns
        self.copper = bool(self.alpha.any())
        self.stages = [(frame, frame_tau), (body, body_tau)]  # (share, time constant): share 0 is no stage

    @classmethod
    def row(cls, model) -> tuple:
        """A model's parameters in the order the arrays hold them (a parameter it lacks is its null)."""
        return tuple(model.params.get(name, null) for name, null in cls.NAMES)

    def forcing(self, effort: np.ndarray, speed: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``(steady_C, rate_per_s)`` each model heads for under ``effort`` (and ``speed``, |velocity|) held (its
        ``dT/dt = rate (steady - T)``); the rate is the winding's own unless copper's coefficient makes it depend
        on the heat."""
        heat = self.b * effort**2
        rise = heat - self.c * effort
        if speed is not None:
            rise = rise + (self.k1 + self.kh) * speed + self.k2 * speed**2
        if not self.copper:
            return self.offset + rise, 1.0 / self.rc
        restoring = np.maximum(1.0 - self.alpha * heat, 1e-6)
        return (self.offset + rise - self.alpha * COPPER_REFERENCE_C * heat) / restoring, restoring / self.rc

    def step(self, state: dict, dt: np.ndarray, effort: np.ndarray, speed: np.ndarray | None) -> dict:
        """One interval ``dt`` from ``state`` (arrays ``winding``, ``output`` and each stage's node, by the term's
        name) under the first sample's inputs held, as ``simulate`` carries a run on: the new state, and the
        ``steady_C`` and ``rate_per_s`` of the second sample's inputs.  ``effort`` and ``speed``: (n, 2)."""
        u0, rate0 = self.forcing(effort[:, 0], None if speed is None else speed[:, 0])
        u1, rate1 = self.forcing(effort[:, 1], None if speed is None else speed[:, 1])
        shaped, out = u0, {}
        # friction put into the housing reaches the winding through the stages, as the ambient does
        boundary = self.offset if speed is None else self.offset + self.kh * speed[:, 0]
        for name, (phi, tau) in zip(STAGES, self.stages):
            heat = shaped - boundary
            a = np.exp(-dt / tau)
            node = state.get(name, self.offset)
            out[name] = a * node + (1.0 - a) * (boundary + phi * heat)
            shaped = node + (1.0 - phi) * heat  # the stage's shaping of the first sample
        a = np.exp(-np.broadcast_to(rate0, dt.shape) * dt)
        winding = a * state["winding"] + (1.0 - a) * shaped
        lag = self.sensor_tau > 0.0
        tau = np.where(lag, self.sensor_tau, 1.0)
        a = np.exp(-dt / tau)
        lagged = a * state["output"] + (1.0 - a) * state["winding"] + (1.0 - tau / dt * (1.0 - a)) * (
            winding - state["winding"])
        out.update(winding=winding, output=np.where(lag, lagged, winding), steady_C=u1,
                   rate_per_s=np.broadcast_to(rate1, dt.shape))
        return out

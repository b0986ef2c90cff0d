"""A new effect is its term and nothing else (issue 80, item 2): a throw-away term written with ``forms`` and
``combine`` -- heat from gear churning, growing as speed to the power 1.5, which no catalog effect has -- is
fitted, found by a diagnosis, stepped for many actuators at once by the arrays the monitor and the Gymnasium
wrapper use, and dropped by ``export`` by what it is (not a Joule heat, not copper's coefficient), with no line
of the suite naming it.  The plant is not tried here: a plant effect is a module of :mod:`thermolimb.effects`,
which this test does not write."""

import numpy as np
import pytest
from conftest import first_order_log

from thermolimb.envs.thermal_wrapper import ModelHeat
from thermolimb.logs import from_frame
from thermolimb.model import Parameter, Term, ThermalModel, register_term
from thermolimb.model.arrays import ModelArrays, one_node, steps_together
from thermolimb.model.saved import bare
from thermolimb.model.signals import Signals
from thermolimb.mujoco_export import Motor, to_dcmotor
from thermolimb.workbench.diagnosis import diagnose
from thermolimb.workbench.validation import fit_and_validate

CHURN_K = 3.0  # K per (rad/s)^1.5


@pytest.fixture()
def churning():
    @register_term
    class GearChurning(Term):
        """Gear oil churned: a rise of ``k |v|^1.5``."""

        name = "gear_churning"
        description = "gear oil churned by speed"
        parameters = (Parameter("churn_K_per_rad1p5", "K/({velocity})^1.5", 0.0, 100.0, 1.0,
                                "rise per speed to the power 1.5", "motion at several speeds"),)
        columns = ("velocity",)
        rise_only = True

        def forms(self, s):
            return (np.abs(s.channel("velocity")) ** 1.5,)

        def combine(self, p, forms):
            return p["churn_K_per_rad1p5"] * forms[0], 0.0

    return GearChurning


def _truth():
    return ThermalModel(("joule", "effort_bias", "gear_churning"),
                        {"RC_s": 80.0, "betaR_K_per_effort2": 0.2, "beta_biasR_K_per_effort": 0.8,
                         "churn_K_per_rad1p5": CHURN_K, "T_offset_C": 26.0})


def _log():
    """Two hours of the plant's random holds and motions, the winding read through the truth with the gear's
    churning, 0.05 K noise and 0.1 degC steps."""
    frame = first_order_log(3).frame.copy()
    s = Signals(frame["time"].to_numpy(), frame["effort"].to_numpy(), frame["velocity"].to_numpy())
    rng = np.random.default_rng(3)
    frame["temperature"] = np.round(_truth().simulate(s, 26.0) + rng.normal(0.0, 0.05, s.n), 1)
    return from_frame(frame.drop(columns=["ambient", "current"])).series("knee")


def test_a_new_term_is_fitted_and_found(churning):
    run = _log()
    report = fit_and_validate([run], ("joule", "effort_bias", "gear_churning"))
    assert report.model.params["churn_K_per_rad1p5"] == pytest.approx(CHURN_K, rel=0.05)
    d = diagnose([run], stability=None)
    churn = next(c for c in d.candidates if c.effect == "gear_churning")
    assert churn.refitted and churn.helps, (churn.status, churn.rmse_K, d.base.validation["rmse_K"])


def test_a_new_term_steps_in_arrays_as_the_model_simulates_it(churning):
    model = _truth()
    assert steps_together(model) and one_node(model)
    other = ThermalModel(("joule", "effort_bias", "speed_losses", "second_node"),
                         {"RC_s": 60.0, "betaR_K_per_effort2": 0.1, "beta_biasR_K_per_effort": 0.0,
                          "speed_K_per_rad_s": 1.0, "speed2_K_per_rad2_s2": 0.5, "frame_fraction": 0.4,
                          "frame_tau_s": 900.0, "T_offset_C": 25.0})
    arrays = ModelArrays([model, other])
    rng = np.random.default_rng(0)
    t, effort, velocity = np.arange(50) * 0.5, rng.uniform(-10, 10, 50), rng.uniform(-3, 3, 50)
    signals = Signals(t, effort, velocity)
    alone = [m.simulate(signals, 40.0) for m in (model, other)]
    keeps = [{}, {}]
    for m, keep in zip((model, other), keeps):  # the first interval as the model runs it, its slow mass placed
        m.simulate(signals.slice(0, 2), 40.0, keep=keep)
    # a model without the slow mass holds its node at its own offset, as the monitor hands it over
    state = {key: np.array([keep.get(key, m.params["T_offset_C"]) for m, keep in zip((model, other), keeps)])
             for key in ("winding", "output", "second_node")}
    for k in range(2, 50):
        pair = np.column_stack([effort[k - 1:k + 1]] * 2).T
        speed = np.abs(np.column_stack([velocity[k - 1:k + 1]] * 2).T)
        state = arrays.step(state, np.full(2, 0.5), pair, speed)
        np.testing.assert_allclose(state["output"], [alone[0][k], alone[1][k]], rtol=1e-9)


def test_the_gymnasium_wrapper_steps_a_new_term_on_its_fast_path(churning):
    heat = ModelHeat([bare(_truth(), "knee", 90.0)], ambient_C=25.0)
    assert heat.fast
    heat.reset(40.0)
    T, _ = heat.step(np.array([6.0]), np.array([2.0]), 0.5, np.array([90.0]))
    held = Signals(np.array([0.0, 0.5]), np.full(2, 6.0), np.full(2, 2.0))
    assert T[0] == pytest.approx(_truth().simulate(held, 40.0)[-1], rel=1e-12)


def test_export_drops_a_new_term_by_what_it_is(churning):
    export = to_dcmotor(bare(_truth(), "knee", 90.0), Motor(0.1, 0.5, 100.0))
    assert export.dropped == ("effort_bias", "gear_churning")
    assert export.exported.terms == ("joule",)

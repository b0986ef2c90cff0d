import numpy as np
import pytest

from thermolimb.model import (
    ModelArrays,
    ModelSpecError,
    Signals,
    ThermalModel,
    first_order_scan,
    parse_model,
)

PARAMS = {"RC_s": 40.0, "betaR_K_per_effort2": 0.02, "beta_biasR_K_per_effort": 0.1, "T_offset_C": 26.0}


def piecewise_effort(n_steps, dt, rng):
    t = np.arange(n_steps + 1) * dt
    effort = np.repeat(rng.uniform(-20, 30, n_steps // 10 + 1), 10)[: n_steps + 1]
    return Signals(t, effort)


def test_scan_equals_loop():
    rng = np.random.default_rng(0)
    a = rng.uniform(0.0, 1.0, 5000)
    a[::7] = 1.0  # no decay
    a[::11] = 0.0  # full reset
    b = rng.normal(size=5000)
    expected = [2.0]
    for k in range(5000):
        expected.append(a[k] * expected[-1] + b[k])
    np.testing.assert_allclose(first_order_scan(a, b, 2.0), expected, rtol=0, atol=1e-10)


def test_exact_prediction_equals_fine_euler():
    """Zero-order-hold exact steps of 2 s equal forward Euler at 1 ms within Euler's O(dt) error."""
    rng = np.random.default_rng(1)
    s = piecewise_effort(300, 2.0, rng)
    model = ThermalModel(("joule", "effort_bias"), PARAMS)
    exact = model.simulate(s, 30.0, method="exact")
    fine_dt = 0.001
    T = 30.0
    fine = [T]
    u = model.equilibrium_C(s)
    for k in range(s.n - 1):
        for _ in range(int(round(2.0 / fine_dt))):
            T += fine_dt / PARAMS["RC_s"] * (u[k] - T)
        fine.append(T)
    # Euler's global error is about dt/(2 RC) of the excursion (~ 1e-5 relative): 2e-3 K is generous.
    np.testing.assert_allclose(exact, fine, atol=2e-3)


def test_constant_effort_follows_closed_form_eq6():
    t = np.linspace(0, 200, 201)
    s = Signals(t, np.full(t.size, 15.0))
    model = ThermalModel(("joule", "effort_bias"), PARAMS)
    steady = 15.0**2 * 0.02 - 15.0 * 0.1 + 26.0
    closed = 30.0 * np.exp(-t / 40.0) + steady * (1 - np.exp(-t / 40.0))
    np.testing.assert_allclose(model.simulate(s, 30.0), closed, rtol=1e-12)


def test_bank_ahead_matches_model_and_gradient():
    models = [ThermalModel(("joule", "effort_bias"), dict(PARAMS, RC_s=rc)) for rc in (10.0, 40.0, 90.0)]
    bank = ModelArrays.from_models(models)
    T0 = np.array([30.0, 70.0, 50.0])
    F = np.array([5.0, -12.0, 20.0])
    ahead = bank.ahead(T0, F, 20.0)
    for i, m in enumerate(models):
        s = Signals(np.array([0.0, 20.0]), np.full(2, F[i]))
        assert ahead[i] == pytest.approx(m.simulate(s, T0[i])[-1], rel=1e-12)
    h = 1e-6
    numeric = (bank.ahead(T0, F + h, 20.0) - bank.ahead(T0, F - h, 20.0)) / (2 * h)
    np.testing.assert_allclose(bank.ahead_gradient(F, 20.0), numeric, rtol=1e-6)
    batch = bank.ahead(T0, np.stack([F, 2 * F]), 20.0)  # leading batch dimension
    assert batch.shape == (2, 3)
    a, b, c = bank.ahead_coefficients(T0, 20.0)  # Eq. 25 as a quadratic in effort, from each term's own rise
    np.testing.assert_allclose(a + b * F + c * F**2, ahead, rtol=1e-12)


def test_model_spec_errors():
    with pytest.raises(ModelSpecError, match="unknown model term.*'joul'.*known terms: joule"):
        parse_model("joul,effort_bias")
    with pytest.raises(ModelSpecError, match="no heat source"):
        parse_model("effort_bias")
    with pytest.raises(ModelSpecError, match="twice"):
        parse_model("joule,joule")
    with pytest.raises(ValueError, match="RC_s must be positive"):
        ThermalModel(("joule",), {"RC_s": 0.0, "betaR_K_per_effort2": 0.1, "T_offset_C": 25.0})


@pytest.mark.parametrize("low, high", [(0.999, 1.0), (0.0, 0.2), (0.9993, 0.9993), (0.05, 0.05), (1.0, 1.0)])
def test_every_scan_path_equals_the_loop(low, high):
    """Slow decay takes the chunked cumulative sums, fast decay the associative scan, one constant factor the
    chunked sums with its powers made once (slow, fast, and none)."""
    rng = np.random.default_rng(5)
    a = rng.uniform(low, high, 20000)
    b = rng.normal(size=20000)
    expected = [0.5]
    for k in range(a.size):
        expected.append(a[k] * expected[-1] + b[k])
    np.testing.assert_allclose(first_order_scan(a, b, 0.5), expected, rtol=0, atol=1e-9)


def test_a_kept_recursion_scans_as_a_fresh_one_and_does_not_pickle():
    """The signals keep a constant rate's recursion for the next scan (a fit's evaluations, a simulation's
    passes): the same one comes back, it scans any inputs as a fresh recursion does, and a pickled copy of the
    signals (a pool's job) leaves it behind."""
    import pickle

    from thermolimb.model.scan import Recursion

    rng = np.random.default_rng(6)
    t = np.cumsum(rng.choice([0.5, 0.5, 1.0, 2.0], 6000))  # irregular intervals of a few lengths: looked up
    s = Signals(t, rng.normal(size=t.size))
    kept = s.recursion(1.0 / 300.0)
    assert s.recursion(1.0 / 300.0) is kept and s.recursion(1.0 / 299.0) is not kept
    fresh = Recursion(np.exp(-np.diff(t) / 300.0))
    for b in (rng.normal(size=t.size - 1), np.zeros(t.size - 1)):
        np.testing.assert_allclose(kept.run(b, 3.0), fresh.run(b, 3.0), rtol=1e-12, atol=1e-12)
    assert "_recursions" not in pickle.loads(pickle.dumps(s)).__dict__


def test_friction_in_the_housing_makes_the_cascade_the_two_node_plant():
    """A winding on a housing (the plant's two-node network, no noise) with speed losses: iron losses heat the
    winding, friction the housing. Fitted on random holds and motions, the cascade with the friction on its slow
    mass (``housing_friction``) is the plant: it predicts a hold at 2 rad/s from rest to the hundredth of a kelvin
    for half an hour. With the friction on the winding (``speed_losses`` alone) it runs 0.78 K off. And a hold
    from rest starts its slow mass where the reading puts it, as if a steady state without the friction's heat
    (the friction at the first sample is an input, as the effort is): started as if that heat had always been
    there, the same model ran up to 2.5 K hot."""
    from dataclasses import replace

    from thermolimb.plant import NETWORKS, X8_9, PlantEffects, simulate_profile
    from thermolimb.plant.duties import held_duty
    from thermolimb.workbench.validation import validate_model

    spec, fx = replace(X8_9, network=NETWORKS["second_order"]), PlantEffects.from_names(["speed_losses"])
    calibration = simulate_profile("random", 3600.0, 1.0, ["knee"], [spec], fx, seed=0).log.series("knee")
    hold = held_duty(spec, fx, 0.5 * spec.continuous_effort, 2.0, 1800.0)
    worst = {}
    for terms in ("joule,speed_losses,second_node,housing_friction", "joule,speed_losses,second_node"):
        model = validate_model([calibration], terms).model
        worst[terms] = np.max(np.abs(model.simulate(hold.signals, hold.start_C) - hold.sensor_C))
    assert worst["joule,speed_losses,second_node,housing_friction"] < 0.01, worst
    assert worst["joule,speed_losses,second_node"] > 0.5, worst  # measured 0.78 K

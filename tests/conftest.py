"""Shared fixtures: small plant logs with known parameters (session-scoped, built once)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from thermolimb.model import TERMS
from thermolimb.plant import (
    FIRST_ORDER_NETWORK,
    X8_9,
    EffortBias,
    PlantEffects,
    Quantisation,
    SensorNoise,
    ThermalPlant,
    run_profile,
)
from thermolimb.plant.profiles import random_holds

BIAS_EFFORT_NM = 2.0
FIRST_ORDER_X8 = replace(X8_9, network=FIRST_ORDER_NETWORK)


def first_order_truth(spec=FIRST_ORDER_X8, bias=BIAS_EFFORT_NM, ambient_C=25.0) -> dict:
    """Eq. 5 parameters of a first-order plant, from its physical data (Jorgensen et al., Eqs. 2-5)."""
    rc, beta_r = spec.first_order(lumped_nodes=1)
    return {"RC_s": rc, "betaR_K_per_effort2": beta_r, "beta_biasR_K_per_effort": 2 * bias * beta_r,
            "T_offset_C": ambient_C + bias**2 * beta_r}


def first_order_log(seed: int, duration_s=2 * 3600.0, dt_s=1.0, motion_probability=0.4):
    """A first-order plant with effort bias, 0.05 K noise and 0.1 degC quantisation, random holds and motions."""
    rng = np.random.default_rng(seed)
    profile = random_holds(duration_s, dt_s, 1, rng, motion_probability=motion_probability)
    effects = PlantEffects(effort_bias=EffortBias(BIAS_EFFORT_NM), sensor_noise=SensorNoise(), quantisation=Quantisation())
    plant = ThermalPlant(["knee"], [FIRST_ORDER_X8], effects, rng=rng)
    return run_profile(plant, profile).log


@pytest.fixture(autouse=True)
def _terms_as_found():
    """Each test leaves the catalog of terms as it found it. A user's terms file loaded with --terms registers its
    terms for the rest of the process, as it should for a user; in tests it made a later file's catalog depend on
    which files pytest-xdist's loadfile put in the same process, which differs between machines (test_together.py
    failed in CI after test_discovery.py had loaded a discovered speed form there)."""
    before = dict(TERMS)
    yield
    TERMS.clear()
    TERMS.update(before)


@pytest.fixture(scope="session")
def truth():
    return first_order_truth()


@pytest.fixture(scope="session")
def two_short_logs():
    """Two half-hour runs of the same first-order plant, other seeds."""
    return [first_order_log(seed, duration_s=1800.0) for seed in (11, 12)]


@pytest.fixture(scope="session")
def plant_log():
    return first_order_log(seed=0)


@pytest.fixture(scope="session")
def holds_log():
    return first_order_log(seed=0, motion_probability=0.0)

"""The seed's recovery experiment end to end (slow): calibrate, heat on one leg, recover without falling."""

import numpy as np
import pytest

from humanoid_pb.actuators import datasheet_bank
from humanoid_pb.constants import ACTUATORS, leg_actuators
from humanoid_pb.params import RECOVERED_C, VALKYRIE, WARNING_C
from humanoid_pb.recovery import calibrate, run_recovery


@pytest.fixture(scope="module")
def bank():
    """Models identified from the robot's own 90 s calibration log (only the slow tests use it)."""
    return calibrate(90.0)[0]


@pytest.mark.slow
def test_calibration_identifies_the_winding_time_constant(bank):
    leg = [ACTUATORS.index(a) for a in leg_actuators("right")]
    assert np.median(bank.RC_s[leg]) == pytest.approx(40.0, rel=0.15)  # 40 s in the plant


@pytest.mark.slow
@pytest.mark.parametrize("strategy", ["thermal_aware", "minimum_effort"])
def test_recovers_from_the_warning_zone_without_falling(bank, strategy):
    run = run_recovery(strategy, bank, max_heat_s=60.0, max_recovery_s=90.0)
    assert run.warning_at_s is not None and run.warning_at_s < 120.0  # the stance leg heats within two minutes
    assert not run.fell
    assert run.recovery_s is not None
    T = np.array(run.temperature_C)
    assert T[-1].max() < RECOVERED_C <= WARNING_C


def test_same_seed_same_run():
    bank = datasheet_bank(VALKYRIE)
    one = run_recovery("minimum_effort", bank, max_heat_s=5.0, max_recovery_s=0.0)
    two = run_recovery("minimum_effort", bank, max_heat_s=5.0, max_recovery_s=0.0)
    np.testing.assert_array_equal(np.array(one.temperature_C), np.array(two.temperature_C))

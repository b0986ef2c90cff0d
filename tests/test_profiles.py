"""What each built-in profile means: its phases, loads, speeds and periods, read from the arrays it returns."""

import numpy as np
import pytest

from thermolimb.plant.profiles import PROFILES, pulses, single_leg, squat, stairs, walking
from thermolimb.util.errors import UsageError

DT = 0.1
WEIGHTS = np.array([1.0, 0.8, 0.6])  # knee, hip, ankle


def rng():
    return np.random.default_rng(0)


@pytest.mark.parametrize("name", sorted(PROFILES))
def test_grid_shape_and_seed(name):
    a = PROFILES[name](600.0, DT, 3, rng())
    b = PROFILES[name](600.0, DT, 3, rng())
    assert a.time_s[0] == 0.0 and a.time_s[-1] == pytest.approx(600.0) and np.allclose(np.diff(a.time_s), DT)
    assert a.load.shape == a.velocity_rad_s.shape == (a.time_s.size, 3)
    np.testing.assert_array_equal(a.load, b.load)
    np.testing.assert_array_equal(a.velocity_rad_s, b.velocity_rad_s)


def test_grid_refuses_too_short_a_run():
    with pytest.raises(UsageError, match="duration_s >= 10 \\* dt_s"):
        squat(0.5, DT, 1, rng())
    for dt_s in (0.0, -0.1):  # a zero or negative interval is refused, not divided by
        with pytest.raises(UsageError, match="duration_s >= 10 \\* dt_s > 0"):
            squat(60.0, dt_s, 1, rng())


def test_a_run_shorter_than_a_second_is_fine_at_a_fast_rate():
    assert len(squat(0.5, 0.01, 1, rng()).time_s) == 51


def test_squat_every_four_and_a_half_minutes():
    p = squat(600.0, DT, 3, rng())
    knee = p.load[:, 0]
    t = p.time_s
    assert np.median(knee[(t > 10) & (t < 90)]) == pytest.approx(1.3, abs=0.02)  # squatting, 90 s hold
    assert np.median(knee[(t > 100) & (t < 260)]) == pytest.approx(0.35, abs=0.02)  # standing
    assert np.median(knee[(t > 280) & (t < 360)]) == pytest.approx(1.3, abs=0.02)  # the next squat at 270 s
    ratio = np.median(p.load[(t > 10) & (t < 90)], axis=0) / np.median(p.load[(t > 10) & (t < 90)][:, 0])
    np.testing.assert_allclose(ratio, WEIGHTS, atol=0.02)
    down = (t > 0) & (t < 3)
    assert p.velocity_rad_s[down, 0].max() > 0.4 and np.all(p.velocity_rad_s[(t > 10) & (t < 90)] == 0)


def test_single_leg_ramps_then_sways():
    p = single_leg(120.0, DT, 3, rng())
    t = p.time_s
    assert np.mean(p.load[t < 0.5, 0]) == pytest.approx(0.3, abs=0.03)
    late = t > 10
    assert np.mean(p.load[late, 0]) == pytest.approx(1.2, abs=0.03)
    sway = p.load[late, 0] - 1.2
    assert np.std(sway) == pytest.approx(0.08 / np.sqrt(2), abs=0.01)  # the sway's amplitude, and little noise
    freqs = np.fft.rfftfreq(late.sum(), DT)
    for signal in (sway, p.velocity_rad_s[late, 0]):  # load and motion sway at 0.3 Hz
        spectrum = np.abs(np.fft.rfft(signal - signal.mean()))
        assert freqs[np.argmax(spectrum[1:]) + 1] == pytest.approx(0.3, abs=0.02)
    assert np.abs(p.velocity_rad_s[:, 0]).max() == pytest.approx(0.05, abs=1e-3)


def test_walking_alternates_bouts_and_rests():
    p = walking(1800.0, DT, 3, rng(), gait_period_s=2.0)
    moving = np.abs(p.velocity_rad_s[:, 0]) > 0
    assert moving[0] and not moving.all()  # starts walking, rests between
    resting_load = p.load[~moving, 0]
    assert np.median(resting_load) == pytest.approx(0.4, abs=0.02)
    bout = moving & (p.time_s < 60.0)
    spectrum = np.abs(np.fft.rfft(p.velocity_rad_s[bout, 0]))
    assert np.fft.rfftfreq(bout.sum(), DT)[np.argmax(spectrum[1:]) + 1] == pytest.approx(0.5, abs=0.05)
    assert np.abs(p.velocity_rad_s[:, 0]).max() == pytest.approx(1.5, abs=0.01)
    assert p.load[bout, 0].max() == pytest.approx(1.2, abs=0.08) and p.load[bout, 0].min() == pytest.approx(0.2, abs=0.08)
    # the limb's actuators are out of phase: the last lags the first by half a period
    assert np.corrcoef(p.velocity_rad_s[bout, 0], p.velocity_rad_s[bout, 2])[0, 1] < -0.9


def test_stairs_steps_through_its_levels_some_at_stall():
    levels = (0.4, 0.9, 1.4, 0.0, 2.2, 0.6)
    p = stairs(600.0, DT, 3, rng())
    step = len(p.time_s) // len(levels)
    for k, level in enumerate(levels):
        chunk = slice(k * step + 5, (k + 1) * step - 5)
        assert np.median(p.load[chunk, 0]) == pytest.approx(level, abs=0.01)
        speed = np.unique(p.velocity_rad_s[chunk, 0])
        assert len(speed) == 1 and speed[0] in (0.0, pytest.approx(0.5 + 0.8 * level))
    stalled = [np.all(p.velocity_rad_s[k * step + 5:(k + 1) * step - 5, 0] == 0) for k in range(len(levels))]
    assert 0 < sum(stalled) < len(levels)
    assert all(stairs(600.0, DT, 1, np.random.default_rng(s), stall_fraction=0.0).velocity_rad_s[:, 0].min() >= 0.5
               for s in range(3))


def test_pulses_are_count_bursts_at_rest_otherwise():
    p = pulses(900.0, DT, 1, rng(), count=3, load=2.5, on_fraction=0.12)
    on = p.load[:, 0] > 1.0
    starts = np.flatnonzero(np.diff(on.astype(int)) == 1)
    assert len(starts) == 3
    assert on.mean() == pytest.approx(0.12, abs=0.01)
    assert np.median(p.load[on, 0]) == pytest.approx(2.5, abs=0.02)
    assert np.median(p.load[~on, 0]) == pytest.approx(0.02, abs=0.01)
    assert np.all(p.velocity_rad_s == 0)
    period = 900.0 / 3
    for k, s in enumerate(starts):
        assert 0.15 * period <= p.time_s[s + 1] - k * period <= 0.25 * period + DT

"""The endurance envelope: cells agree computed two ways, strategies buy time where vertical forces derate, and
the propagation follows a whole PyBullet run (the shortcut itself: tests/test_periodic.py)."""

import numpy as np
import pytest

from hexapod_pb.experiments import endurance


def test_sharing_the_load_buys_time_where_vertical_forces_derate_within_the_hour():
    vertical = endurance.endurance(80.0, 40.0, "stand", "vertical_only", 3600.0)
    minimax = endurance.endurance(80.0, 40.0, "stand", "minimax", 3600.0)
    assert vertical.time_to_derate_s is not None and vertical.time_to_derate_s < 3600.0
    assert minimax.time_to_derate_s is None or minimax.time_to_derate_s > 2 * vertical.time_to_derate_s


def test_a_cell_computed_two_ways_agrees():
    """In one go, or in two windows, the second re-measured in PyBullet from the propagated state."""
    one = endurance.endurance(80.0, 40.0, "stand", "vertical_only", 3600.0)
    cycle = endurance.measure_cycle(80.0, "stand", "vertical_only", 40.0)
    state = np.full(cycle.map.M.shape[0], 40.0)
    first = cycle.map.propagate(state, 240.0)
    again = endurance.measure_cycle(80.0, "stand", "vertical_only", 40.0, state=first.final_state)
    rest = again.map.propagate(first.final_state, 3600.0, endurance.derating_threshold_C())
    elapsed = len(first.cycle_start_s) * cycle.map.period_s
    assert elapsed + rest.crossing.time_s == pytest.approx(one.time_to_derate_s, abs=cycle.map.period_s)


def test_same_seed_same_cell():
    a = endurance.endurance(20.0, 25.0, "walk", "minimax", 1800.0, seed=3)
    b = endurance.endurance(20.0, 25.0, "walk", "minimax", 1800.0, seed=3)
    assert a.row() == b.row()


def test_a_load_the_legs_cannot_hold_is_a_fall_not_a_time():
    cell = endurance.endurance(120.0, 25.0, "stand", "vertical_only", 3600.0)
    assert cell.fell and cell.time_to_derate_s is None and cell.distance_per_s_m == 0.0


def test_thermal_strategies_need_identified_models():
    with pytest.raises(ValueError, match="identified"):
        endurance.endurance(20.0, 25.0, "walk", "thermal_aware", 600.0)


@pytest.mark.slow
def test_propagation_follows_twenty_minutes_of_pybullet():
    check = endurance.check_periodic(20.0, 40.0, "walk", "vertical_only", 1200.0)
    assert check.duration_s >= 1200.0
    rise = check.pybullet_hottest_C[-1] - 40.0
    assert abs(check.final_difference_K) < 0.1 * rise, check.summary()


def test_a_pause_joins_standing_to_the_strides():
    walk = endurance.measure_cycle(20.0, "walk", "vertical_only", 25.0)
    paused = endurance.measure_cycle(20.0, "walk", "vertical_only", 25.0, endurance.Gait(pause_share=0.2))
    assert paused.map.period_s == pytest.approx(walk.map.period_s / 0.8, rel=0.01)
    assert paused.distance_per_s_m == pytest.approx(0.8 * walk.distance_per_s_m, rel=0.01)
    # standing on six legs halves each stance leg's load: the pause cools the hottest winding
    assert paused.map.steady_peak_C().max() < walk.map.steady_peak_C().max() - 1.0
    with pytest.raises(ValueError, match="pause_share"):
        endurance.Gait(pause_share=1.0)

"""Behaviour a mutation run (benchmarks/mutation.py) found unpinned: each test names what a slip would change."""

import numpy as np
import pandas as pd
import pytest

from thermolimb.identification import IdentifiabilityError
from thermolimb.identification.calibration import identify_bank
from thermolimb.model import ModelArrays, ThermalModel
from thermolimb.plant import FIRST_ORDER_NETWORK, X8_9, X8_16, PlantEffects, ThermalPlant, run_profile
from thermolimb.plant.profiles import random_holds
from thermolimb.workbench.diagnosis.residuals import analyse_residuals


def _plant_log(seed=0, duration_s=1800.0, idle=True):
    names = ["knee", "hip", "wrist"]
    specs = [X8_9, X8_16, X8_9]
    specs = [s.__class__(**{**s.__dict__, "network": FIRST_ORDER_NETWORK, "driver": None}) for s in specs]
    plant = ThermalPlant(names, specs, effects=PlantEffects.realistic_sensor(), rng=np.random.default_rng(seed))
    profile = random_holds(duration_s, 1.0, 3, np.random.default_rng(seed))
    if idle:
        profile.load[:, 2] *= 0.01  # the wrist barely works: its log cannot show its heating
    return run_profile(plant, profile).log, specs


def test_identify_bank_finds_each_actuator_and_gives_idle_ones_the_prior():
    log, specs = _plant_log()
    limits = np.array([s.effort_limit for s in specs])
    bank = identify_bank(log, ["knee", "hip", "wrist"], limits, model="joule", min_rise_K=0.5)
    truth = ModelArrays.from_specs(specs).betaR_K_per_effort2
    rc = specs[0].first_order()[0]
    np.testing.assert_allclose(bank.betaR_K_per_effort2[:2], truth[:2], rtol=0.05)
    np.testing.assert_allclose(bank.RC_s[:2], rc, rtol=0.05)
    # the wrist gets the prior: the identified ones' median heating per squared limit, on its own limit
    prior = np.median(bank.betaR_K_per_effort2[:2] * limits[:2] ** 2) / limits[2] ** 2
    assert bank.betaR_K_per_effort2[2] == pytest.approx(prior)
    assert bank.RC_s[2] == pytest.approx(np.median(bank.RC_s[:2]))
    assert bank.beta_biasR_K_per_effort[2] == 0.0
    assert bank.T_offset_C[2] == pytest.approx(np.mean(log.series("wrist").temperature_C))
    # the order asked for is the order returned
    swapped = identify_bank(log, ["hip", "knee", "wrist"], limits[[1, 0, 2]], model="joule", min_rise_K=0.5)
    np.testing.assert_allclose(swapped.betaR_K_per_effort2[:2], bank.betaR_K_per_effort2[[1, 0]])
    # without the minimum rise the idle wrist's fit is believed
    believed = identify_bank(log, ["knee", "hip", "wrist"], limits, model="joule")
    assert believed.betaR_K_per_effort2[2] != pytest.approx(prior)


def test_identify_bank_refuses_a_log_that_identifies_nothing():
    log, specs = _plant_log(duration_s=600.0)
    with pytest.raises(IdentifiabilityError, match="identifies no actuator: it needs efforts that vary"):
        identify_bank(log, ["wrist"], np.array([20.0]), min_rise_K=0.5)
    with pytest.raises(IdentifiabilityError, match="identifies no actuator"):
        identify_bank(log, ["knee"], np.array([20.0]), min_rc_s=1e6)


def test_bank_refuses_models_beyond_eq5_naming_the_terms():
    model = ThermalModel(("joule", "winding_tempco"), {"RC_s": 50.0, "betaR_K_per_effort2": 0.1, "alpha_per_K": 0.004,
                                               "T_offset_C": 25.0})
    with pytest.raises(ValueError, match=r"holds Eq. 5 only; model has extra terms \['winding_tempco'\]"):
        ModelArrays.from_models([model])


def test_realistic_sensor_is_noise_and_steps():
    fx = PlantEffects.realistic_sensor()
    assert fx.names == ("sensor_noise", "quantisation")
    assert fx.sensor_noise.std_K == 0.05 and fx.quantisation.step_K == 0.1


def test_residual_analysis_json_names_each_cross_correlation():
    log, _ = _plant_log(duration_s=900.0, idle=False)
    series = log.series("knee")
    report = analyse_residuals(series, series.temperature_C + 0.1 * np.sin(series.time_s / 50.0)).to_json()
    assert set(report) == {"rmse_K", "autocorrelation_significant", "cross_correlation", "phase_rmse_K"}
    assert report["rmse_K"] == pytest.approx(0.1 / np.sqrt(2), rel=0.05)
    for entry in report["cross_correlation"].values():
        assert set(entry) == {"peak_lag_s", "peak", "band", "significant"}
        assert entry["band"] > 0 and isinstance(entry["significant"], bool)


# ------------------------------------------------------------------ logs: what the reader says and reads
def test_gap_sentence_counts_only_runs_too_short(tmp_path):
    import pandas as pd

    from thermolimb.logs import read_log
    from thermolimb.logs.series import MIN_SAMPLES

    t = np.concatenate([np.arange(MIN_SAMPLES), 5000.0 + np.arange(40.0), 9000.0 + np.arange(5.0)])
    pd.DataFrame({"time": t, "actuator": "knee", "effort": 1.0, "temperature": 25.0}).to_csv(tmp_path / "g.csv",
                                                                                           index=False)
    sentence = read_log(tmp_path / "g.csv").describe_gaps("knee")
    assert f"1 run(s) shorter than {MIN_SAMPLES} samples left out" in sentence  # the 5-sample run, not the first
    assert f"{5000 - (MIN_SAMPLES - 1):.0f} s at t = {MIN_SAMPLES - 1:.0f} s" in sentence and "into 3 runs" in sentence


def test_a_byte_order_mark_is_not_part_of_the_first_column(tmp_path):
    from thermolimb.logs import read_log

    rows = "\n".join(f"{k},knee,1.0,{25 + 0.01 * k}" for k in range(30))
    (tmp_path / "bom.csv").write_text("time,actuator,effort,temperature\n" + rows + "\n", encoding="utf-8-sig")
    log = read_log(tmp_path / "bom.csv")
    assert log.series("knee").time_s[-1] == 29.0


def test_per_channel_time_columns_need_the_temperatures(tmp_path):
    import pandas as pd

    from thermolimb.logs import LogError, parse_mapping, read_log

    pd.DataFrame({"te": np.arange(30.0), "e": 1.0, "tt": np.arange(30.0), "T": 25.0}).to_csv(tmp_path / "w.csv",
                                                                                          index=False)
    with pytest.raises(LogError, match=r"w.csv: with per-channel time columns, --map names "
                                       r"temperature=COLUMN@TIME_COLUMN \(or time=COLUMN"):
        read_log(tmp_path / "w.csv", parse_mapping("effort=e@te,temperature=T"), actuator_name="hip")


def test_joint_patterns_without_a_common_joint_list_each(tmp_path):
    import pandas as pd

    from thermolimb.logs import LogError, parse_mapping, read_log

    pd.DataFrame({"t": np.arange(30.0), "temp_1": 25.0, "temp_2": 25.0, "eff_3": 1.0}).to_csv(tmp_path / "j.csv",
                                                                                          index=False)
    with pytest.raises(LogError, match=r"no joint number has a column for every pattern of --map "
                                       r"(temperature: joints \[1, 2\]; effort: joints \[3\]|"
                                       r"effort: joints \[3\]; temperature: joints \[1, 2\])"):
        read_log(tmp_path / "j.csv", parse_mapping("time=t,temperature=temp_{j},effort=eff_{j}"))


def test_a_csv_the_parser_cannot_read_is_named(tmp_path):
    from thermolimb.logs import LogError, read_log

    rows = "\n".join(f"{k},knee,1.0,{25 + 0.01 * k}" for k in range(30))
    (tmp_path / "bad.csv").write_text("time,actuator,effort,temperature\n" + rows + "\n1,knee,1,2,3,4,5\n")
    with pytest.raises(LogError, match=r"bad.csv: cannot be read as a comma-separated CSV file"):
        read_log(tmp_path / "bad.csv")


def test_timestamps_in_different_offsets_are_one_clock():
    import pandas as pd

    from thermolimb.logs.table import first_stamp

    stamps = pd.Series(["2024-01-01T01:00:00+01:00", "2024-01-01T00:00:01+00:00", "2024-01-01T00:00:02Z"])
    first = first_stamp(stamps)
    assert first == pd.Timestamp("2024-01-01T00:00:00", tz="UTC")


def test_a_folder_is_a_bag_only_with_its_metadata(tmp_path):
    from thermolimb.logs.formats import is_bag

    (tmp_path / "run.csv").write_text("time,temperature\n")
    assert not is_bag(tmp_path) and not is_bag(tmp_path / "run.csv")
    assert is_bag(tmp_path / "x.bag") and is_bag(tmp_path / "x.mcap") and is_bag(tmp_path / "x.db3")
    (tmp_path / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n")
    assert is_bag(tmp_path)


def _analysis(phases: dict[str, float]):
    from thermolimb.workbench.diagnosis.residuals import Correlation, ResidualAnalysis

    lags = np.array([0.0, 30.0, 60.0])
    effort = Correlation(lags, np.array([0.6, 0.3, 0.1]), 0.1)
    return ResidualAnalysis(np.arange(3.0), np.zeros(3), Correlation(lags, np.array([1.0, 0.5, 0.25]), 0.1),
                            {"effort": effort, "effort^2": effort}, phases)


@pytest.mark.parametrize("hot, cool, verdict", [(0.5, 0.2, "worse"), (0.2, 0.5, "not worse")])
def test_tempco_evidence_is_the_hot_and_cool_fits_not_the_effort(hot, cool, verdict):
    """The tempco term scales the effort's heating, so its evidence is where the fit fails (hot), not a correlation
    with the effort (which every heat term shares)."""
    from thermolimb.workbench.diagnosis.candidates import Candidate
    from thermolimb.workbench.diagnosis.explain import describe

    text = describe(Candidate("winding_tempco", ("joule", "winding_tempco"), p_value=0.003),
                    _analysis({"hot": hot, "cool": cool}), 0.5)
    assert text.startswith(f"the fit is {verdict} when hot (RMSE {hot:.2f} K hot vs {cool:.2f} K cool)")
    assert "score test p = 0.003" in text and "correlate" not in text


def test_slow_effects_are_looked_for_in_time_and_inputs_in_their_channel():
    from thermolimb.workbench.diagnosis.candidates import Candidate
    from thermolimb.workbench.diagnosis.explain import describe

    analysis = _analysis({"heating": 0.4, "cool": 0.1})
    slow = describe(Candidate("second_node", ("joule", "second_node")), analysis, 0.5)
    assert slow.startswith("looking for a slow drift: residual autocorrelation +0.25 at 60 s, RMSE 0.40 K heating")
    joule = describe(Candidate("joule", ("joule",)), analysis, 0.5)
    assert joule.startswith("the residual correlates with effort^2 (peak +0.60 at lag 0 s")


def test_autocorrelation_band_and_lags_are_the_textbook_ones():
    """The residual's autocorrelation: lags 0..max at the sampling interval, the white-noise band 1.96/sqrt(n);
    a cross-correlation spans -max..+max."""
    from thermolimb.workbench.diagnosis.residuals import Z95, cross_correlation

    log, _ = _plant_log(duration_s=900.0, idle=False)
    series = log.series("knee")
    analysis = analyse_residuals(series, series.temperature_C + 0.1 * np.sin(series.time_s / 50.0))
    assert analysis.autocorrelation.band == pytest.approx(Z95 / np.sqrt(series.n))
    assert analysis.autocorrelation.significant  # a 314 s sine left in the residual
    lags, r = cross_correlation(np.sin(np.arange(200.0)), np.cos(np.arange(200.0)), 7)
    np.testing.assert_array_equal(lags, np.arange(-7, 8))
    assert len(r) == 15


def test_sensor_lag_is_exact_for_a_winding_that_moves_linearly():
    """First-order hold: a ramp seen through tau dTs/dt = T - Ts is T(t) - r tau (1 - exp(-t/tau)), on a uniform
    time grid (one interval) and on an uneven one."""
    from thermolimb.effects.sensor_lag import SensorLagTerm as SensorLag
    from thermolimb.model.signals import Signals

    uniform = np.arange(0.0, 300.0, 2.0)
    uneven = np.cumsum(np.r_[0.0, np.random.default_rng(0).uniform(0.5, 3.5, 149)])
    for t in (uniform, uneven):
        signals = Signals(time_s=t, effort=np.zeros(t.size))
        assert (signals.uniform_dt_s is not None) == (t is uniform)
        winding = 30.0 + 0.05 * t
        lagged = SensorLag().shape_output({"sensor_tau_s": 25.0}, signals, winding, 30.0)
        np.testing.assert_allclose(lagged, winding - 0.05 * 25.0 * (1.0 - np.exp(-t / 25.0)), atol=1e-9)


def test_a_log_keeps_only_its_canonical_columns(tmp_path):
    """Reading (and leaving out incomplete samples) re-indexes rows without adding an index column."""
    from thermolimb.logs import read_log

    t = np.arange(100.0)
    frame = pd.DataFrame({"time": t, "actuator": "knee", "effort": 5 + np.sin(t / 9), "temperature": 30 + 0.01 * t,
                          "velocity": np.cos(t / 9), "comment": "x"})
    frame.loc[3, "velocity"] = np.nan
    path = tmp_path / "log.csv"
    frame.to_csv(path, index=False)
    log = read_log(path, drop_incomplete=True)
    assert list(log.frame.columns) == ["time", "actuator", "effort", "temperature", "velocity"]
    assert list(log.frame.index) == list(range(99))


def test_tempco_scales_the_current_heating_too():
    """Copper's coefficient multiplies every Joule term the model has, the current's as well as the effort's."""
    from types import SimpleNamespace

    from thermolimb.constants import COPPER_REFERENCE_C
    from thermolimb.effects.winding_tempco import WindingTempcoTerm as WindingTempco

    s = SimpleNamespace(effort=np.array([2.0, 4.0]), current_A=np.array([3.0, 1.0]), air_shift_K=0.0)
    p = {"betaR_K_per_effort2": 0.5, "currentR_K_per_A2": 0.2, "alpha_per_K": 0.0039}
    joule = 0.5 * s.effort**2 + 0.2 * s.current_A**2
    constant, per_kelvin = WindingTempco().contribution(p, s)
    np.testing.assert_allclose(per_kelvin, 0.0039 * joule)
    np.testing.assert_allclose(constant, -0.0039 * COPPER_REFERENCE_C * joule)
    # a run read 10 K lower to share the air of the runs fitted with it (common_air): its copper is as hot as read
    s.air_shift_K = 10.0
    constant, _ = WindingTempco().contribution(p, s)
    np.testing.assert_allclose(constant, -0.0039 * (COPPER_REFERENCE_C - 10.0) * joule)


def test_sensor_noise_is_drawn_per_actuator():
    """Two actuators at the same temperature read differently: each thermistor has its own noise."""
    from thermolimb.plant import SensorNoise

    plant = ThermalPlant(["a", "b"], [X8_9, X8_9], effects=PlantEffects(sensor_noise=SensorNoise()),
                         rng=np.random.default_rng(0))
    readings = np.array([plant.read(plant.winding_C) for _ in range(50)])
    assert not np.allclose(readings[:, 0], readings[:, 1])
    assert readings.std(axis=0) == pytest.approx(np.full(2, SensorNoise().std_K), rel=0.3)

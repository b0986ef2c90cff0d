"""The model travels: exported to MuJoCo's dcmotor it integrates there as here; ThermalWrapper heats the joints of
Gymnasium's MuJoCo environments and of this suite's PyBullet robots exactly as the model does; the audit says
which joint limits a policy."""

import json

import gymnasium as gym
import numpy as np
import pytest

from thermolimb.cli.main import main
from thermolimb.logs import read_log
from thermolimb.model import ThermalModel
from thermolimb.model.saved import ModelFile, bare
from thermolimb.plant import X8_9

mujoco = pytest.importorskip("mujoco")
from gymnasium.utils.env_checker import check_env  # noqa: E402

from thermolimb.envs.thermal_wrapper import ThermalWrapper  # noqa: E402
from thermolimb.mujoco_export import Motor, mjcf_snippet, run_in_mujoco, to_dcmotor  # noqa: E402


@pytest.fixture(scope="module")
def calibration(tmp_path_factory):
    """A plant log (a winding on a housing, so the fitted model is not the plant) and the model fit saved."""
    folder = tmp_path_factory.mktemp("travel")
    log, model = folder / "cal.csv", folder / "model.json"
    assert main(["simulate", "--profile", "random", "--duration", "1800", "--dt", "1", "--seed", "3",
                 "--out", str(log), "--quiet"]) == 0
    assert main(["fit", str(log), "--actuator", "knee", "--save", str(model), "--limit-C", "90", "--quiet"]) == 0
    return log, model


def test_mujoco_integrates_the_exported_actuator_within_half_a_percent_of_the_rise(calibration):
    log, model = calibration
    saved = ModelFile.load(model)["knee"]
    export = to_dcmotor(saved, Motor(motor_const=0.12, resistance_ohm=0.8, gear=12.0))
    series = read_log(log).series("knee")
    mujoco_C = run_in_mujoco(export, series.signals, float(series.temperature_C[0]))
    ours = export.exported.simulate(series.signals, float(series.temperature_C[0]))
    rise = ours.max() - ours.min()
    assert rise > 5.0 and np.max(np.abs(mujoco_C - ours)) < 0.005 * rise
    assert export.dropped == ("effort_bias",)


def test_the_snippet_is_mjcf_that_mujoco_reads_back(calibration):
    saved = ModelFile.load(calibration[1])["knee"]
    export = to_dcmotor(saved, Motor(0.12, 0.8, 12.0))
    snippet = mjcf_snippet([export])
    actuator = snippet[snippet.index("<actuator>"):]
    xml = (f'<mujoco><worldbody><body><joint name="knee" type="hinge"/><geom size=".05" mass="1"/></body>'
           f'</worldbody>{actuator}</mujoco>')
    m = mujoco.MjModel.from_xml_string(xml)
    assert m.na == 1  # the thermal state, one activation
    data = mujoco.MjData(m)
    data.ctrl[0] = 1.0  # N m at the motor: 12 N m at the joint, i = 1 / 0.12 A
    for _ in range(int(20 * saved.model.params["RC_s"] / m.opt.timestep)):
        mujoco.mj_step(m, data)
    steady = saved.model.params["betaR_K_per_effort2"] * 12.0**2  # the model's rise at 12 N m
    assert data.act[0] == pytest.approx(steady, rel=1e-3)


def test_export_says_what_it_drops_and_what_that_costs(calibration, capsys):
    log, model = calibration
    assert main(["export", str(model), str(log), "--to", "mujoco", "--motor-const", "0.12", "--resistance", "0.8",
                 "--gear", "12", "--actuator", "knee", "--json"]) == 0
    out = capsys.readouterr()
    record = json.loads(out.out)
    assert record["dropped"] == ["effort_bias"] and record["check"]["share_of_rise"] < 0.005
    assert record["cost"]["exported_rmse_K"] > 0 and "effort_bias dropped" in out.err
    # the target is a format choice (the one so far, the default); the earlier spelling --mujoco still reads
    assert main(["export", str(model), "--mujoco", "--motor-const", "0.12", "--resistance", "0.8", "--gear", "12",
                 "--actuator", "knee", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["thermal"] == {k: v for k, v in record["thermal"].items()}
    with pytest.raises(SystemExit) as refused:
        main(["export", str(model), "--to", "mujoco", "--resistance", "0.8"])
    assert refused.value.code == 2 and "--motor-const" in capsys.readouterr().err


def test_export_says_once_what_dropping_several_terms_costs(calibration, tmp_path, capsys):
    """A model with speed losses beside the bias: both are dropped, in one sentence with the cost of dropping both
    (a sentence per term repeated the same cost, as if each cost it)."""
    log, _ = calibration
    model = tmp_path / "speed.json"
    assert main(["fit", str(log), "--actuator", "knee", "--model", "joule,effort_bias,speed_losses", "--save",
                 str(model), "--quiet"]) == 0
    capsys.readouterr()
    assert main(["export", str(model), str(log), "--to", "mujoco", "--motor-const", "0.12", "--resistance", "0.8",
                 "--gear", "12", "--actuator", "knee"]) == 0
    said = [line for line in capsys.readouterr().err.splitlines() if "dropped" in line]
    assert len(said) == 1 and "effort_bias and speed_losses dropped" in said[0] and "K RMSE" in said[0], said


def _torques_and_temperatures(env, steps, seed=0):
    obs, info = env.reset(seed=seed)
    env.action_space.seed(seed)
    torques, temperatures = [], [info["temperature_C"]]
    for _ in range(steps):
        obs, _, terminated, truncated, info = env.step(env.action_space.sample())
        torques.append(info["torque_Nm"])
        temperatures.append(info["temperature_C"])
        assert not (terminated or truncated)
    return np.array(torques), np.array(temperatures)


@pytest.mark.parametrize("env_id", ["Ant-v5", "Humanoid-v5"])
def test_a_wrapped_mujoco_environment_passes_check_env_and_heats_as_the_model(calibration, env_id):
    saved = ModelFile.load(calibration[1])["knee"]
    env = ThermalWrapper(gym.make(env_id, terminate_when_unhealthy=False), models=saved)
    check_env(env, skip_render_check=True)
    torques, temperatures = _torques_and_temperatures(env, 100)
    assert env.observation_space.contains(env.reset(seed=1)[0])
    dt = env.unwrapped.dt
    for k in (0, len(env.joints) - 1):  # the model's own exact simulation of the torques read, joint by joint
        from thermolimb.model.signals import Signals

        s = Signals(np.arange(101) * dt, np.r_[torques[:, k], torques[-1, k]])
        expected = saved.model.simulate(s, 25.0)
        np.testing.assert_allclose(temperatures[:, k], expected, rtol=0, atol=1e-9)
    assert np.all(temperatures[-1] > 25.0)


def test_a_wrapped_environment_in_another_air_moves_the_model_s_offset_with_it(calibration):
    """The model was identified at 25 degC; in a 45 degC room its offset follows the air (Jorgensen et al. Eq. 5),
    as predict and the monitor do: an idle joint that starts at the air's temperature stays there."""
    saved = ModelFile.load(calibration[1])["knee"]
    for ambient in (25.0, 45.0):
        env = ThermalWrapper(gym.make("Ant-v5"), models=saved, ambient_C=ambient)
        env.reset(seed=0)
        offset = env.heat.models[0].params["T_offset_C"]
        assert offset == pytest.approx(saved.model.params["T_offset_C"] + ambient - 25.0)
        for _ in range(200):
            info = env.step(np.zeros(8, np.float32))[-1]
        # idle: each winding relaxes from the air's temperature towards the offset, whichever air
        bias = saved.model.params["T_offset_C"] - 25.0  # the offset's own distance from the air it was fitted in
        assert np.all(np.abs(info["temperature_C"] - ambient) <= abs(bias) + 1e-9)
        env.close()


def test_the_same_seed_heats_the_same_and_a_vector_of_wrapped_environments_works():
    def make():
        return ThermalWrapper(gym.make("Ant-v5"), plant=X8_9, observe="dict")

    a, b = make(), make()
    ta = _torques_and_temperatures(a, 20, seed=7)[1]
    tb = _torques_and_temperatures(b, 20, seed=7)[1]
    assert np.array_equal(ta, tb)
    envs = gym.vector.SyncVectorEnv([make, make])
    obs, info = envs.reset(seed=[1, 2])
    assert obs["temperature_C"].shape == (2, 8)
    obs, _, _, _, info = envs.step(envs.action_space.sample())
    assert info["temperature_C"].shape == (2, 8) and np.all(obs["temperature_C"] > 24.0)
    envs.close()


def test_protection_derates_and_overheating_ends_the_episode():
    hot = ThermalModel(("joule",), {"RC_s": 2.0, "betaR_K_per_effort2": 1.0, "T_offset_C": 25.0})
    saved = bare(hot, "any", limit_C=60.0)

    def run(**options):
        env = ThermalWrapper(gym.make("Ant-v5"), models=saved, **options)
        env.reset(seed=0)
        peak, ended = 25.0, False
        for _ in range(60):
            _, reward, terminated, _, info = env.step(np.ones(8, np.float32))
            peak = max(peak, float(info["temperature_C"].max()))
            if terminated:
                ended = True
                break
        return peak, ended, info

    free_peak, free_ended, _ = run()
    protected_peak, _, info = run(protect=True)
    _, ended, info = run(terminate=True)
    assert free_peak > 60.0 and not free_ended
    assert protected_peak < free_peak and ended and info["overheated"]


def test_the_suite_s_pybullet_robot_wrapped(calibration):
    from hexapod_pb import ENV_ID

    saved = ModelFile.load(calibration[1])["knee"]
    env = ThermalWrapper(gym.make(ENV_ID, max_time_s=2.0), models=saved, observe="append")
    check_env(env, skip_render_check=True)
    obs, info = env.reset(seed=0)
    assert len(env.joints) == 18 and obs.shape == env.observation_space.shape
    obs, _, _, _, info = env.step(env.action_space.sample())
    assert np.any(np.abs(info["torque_Nm"]) > 0.1) and np.all(info["temperature_C"] >= 25.0)
    assert info["temperature_C"].max() > 25.0  # the stance legs' torques heat their joints
    env.close()


def test_the_audit_names_the_limiting_joint(tmp_path, capsys):
    assert main(["audit", "--env", "Ant-v5", "--policy", "random", "--duration", "20", "--plant", "x8-9",
                 "--limit-C", "40", "--json", "--plot", str(tmp_path)]) == 0
    record = json.loads(capsys.readouterr().out)
    first = [j for j in record["joints"] if j["time_to_limit_s"] is not None]
    assert first and record["limiting_joint"] == min(first, key=lambda j: j["time_to_limit_s"])["joint"]
    assert (tmp_path / "audit.png").exists()
    for argv, message in ((["--policy", "nowhere:thing"], "cannot import nowhere"),
                          (["--env", "NoSuchEnv-v0"], "--env NoSuchEnv-v0"),
                          (["--env-arg", "no_such_argument=1"], "does not take the arguments given"),
                          (["--env-arg", "novalue"], "expected KEY=VALUE"),
                          (["--policy", "json:loads"], "cannot be called as loads(env, observation)"),
                          (["--limit-C", "20"], "8 of 8 joints start at or above their limit")):
        base = ["audit", "--env", "Ant-v5", "--duration", "1"]
        assert main(base + argv) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1


def test_an_audit_beyond_the_model_s_log_says_its_temperatures_are_extrapolated(calibration, capsys):
    """Ant-v5's random actions reach 150 N m at every joint; the model was identified on a knee's 20 N m."""
    assert main(["audit", "--env", "Ant-v5", "--policy", "random", "--duration", "5", "--models",
                 str(calibration[1]), "--json"]) == 0
    notes = json.loads(capsys.readouterr().out)["notes"]
    assert any("8 of 8 joints were driven beyond the torques their model was identified on" in n for n in notes), notes
    assert main(["audit", "--env", "Ant-v5", "--policy", "zero", "--duration", "5", "--models",
                 str(calibration[1]), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["notes"] == []  # at rest, nothing beyond its log


def test_the_time_to_a_limit_is_when_the_first_order_response_crosses_it():
    from thermolimb.envs.thermal_wrapper import reach_s

    T, steady, limit, rc = np.array([30.0, 80.0, 95.0, 50.0]), np.array([120.0, 60.0, 120.0, 100.0]), \
        np.full(4, 90.0), np.array([100.0, 100.0, 50.0, 200.0])
    got = reach_s(T, steady, 1.0 / rc, limit)
    t = np.linspace(0.0, 2000.0, 200001)
    for k in range(4):
        path = steady[k] + (T[k] - steady[k]) * np.exp(-t / rc[k])
        crossed = np.flatnonzero(path >= limit[k])
        expected = np.inf if not crossed.size else t[crossed[0]]
        assert got[k] == pytest.approx(expected, abs=0.02), (k, got[k], expected)


def test_the_audit_figure_names_the_hottest_joints_and_says_what_the_grey_lines_are(tmp_path):
    """Eight joints: the six hottest are named, and the two others are one grey entry of the legend."""
    import matplotlib.pyplot as plt

    from thermolimb.envs.audit import AuditResult
    from thermolimb.plotting.audit import plot_audit

    time_s = np.linspace(0.0, 60.0, 61)
    peaks = np.arange(8) + 30.0
    result = AuditResult("Toy-v0", "random", tuple(f"j{k}" for k in range(8)), time_s,
                         25.0 + np.outer(time_s / 60.0, peaks - 25.0), np.full(8, 80.0), 0, "the suite's plant")
    captured = {}
    real_save = plt.Figure.savefig

    def savefig(fig, *args, **kwargs):
        captured["labels"] = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
        return real_save(fig, *args, **kwargs)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(plt.Figure, "savefig", savefig)
        plot_audit(result, tmp_path / "audit.png")
    assert captured["labels"] == ["j2", "j3", "j4", "j5", "j6", "j7", "2 other joints, lower peaks", "limit 80 degC"]


def _ur3_saved(joint: str):
    """The UR3's first run of ``joint`` and Jorgensen et al.'s model fitted on its first 70 %, its effort the motor
    current (A), as benchmarks/travel.py exports it."""
    from dataclasses import replace

    from thermolimb.data import REAL_LOGS
    from thermolimb.workbench.saving import saved_from_report
    from thermolimb.workbench.validation import Scheme, validate_model

    runs = REAL_LOGS["ur3"].read()[0].runs(joint)[:1]
    saved = saved_from_report(validate_model(runs, "joule,effort_bias", Scheme.at_split(0.7)), [])
    return runs, replace(saved, channel_units={**saved.channel_units, "effort": "A"})


def test_a_refit_on_the_log_carries_what_dropping_a_term_loses():
    """The UR3's J1 (real, its first run; heat from the motor current with a bias the data pins down): the saved
    model without its bias misses its own log by 16.7 K RMSE; the one node MuJoCo holds, fitted again on that log,
    by 0.04 K (docs/travel.md)."""
    from thermolimb.mujoco_export import cost_of_dropping, refitted

    runs, saved = _ur3_saved("J1")
    export = to_dcmotor(saved, Motor(0.1, 1.0, 10.0))
    again = refitted(saved, export, runs)
    assert again.dropped == export.dropped == ("effort_bias",) and again.exported.terms == ("joule",)
    truncated, refit = (cost_of_dropping(saved, e, runs)["exported_rmse_K"] for e in (export, again))
    assert truncated > 10.0 and refit < 0.1, (truncated, refit)


def test_export_refit_needs_a_log_and_exports_the_refitted_node(calibration, capsys):
    log, model = calibration
    argv = ["export", str(model), "--to", "mujoco", "--motor-const", "0.12", "--resistance", "0.8", "--gear", "12",
            "--actuator", "knee", "--refit"]
    assert main(argv) == 2 and "give the model's calibration LOG" in capsys.readouterr().err
    assert main(argv[:2] + [str(log)] + argv[2:] + ["--json"]) == 0
    out = capsys.readouterr()
    record = json.loads(out.out)
    assert record["refit"]["exported"] and record["cost"]["exported_rmse_K"] == record["refit"]["rmse_K"]
    assert record["thermal"]["timeconst_s"] == pytest.approx(record["refit"]["params"]["RC_s"])
    assert "refitted on the log without them" in out.err and record["check"]["share_of_rise"] < 0.005


def test_an_export_whose_heat_gain_is_nil_says_the_joint_will_not_heat():
    """The UR3's J5 (real): its saved model puts its heat in the bias, Joule heating at its bound (1.3e-16 against a
    standard error of 6.1 K/A^2); one node without the bias would not heat in MuJoCo, refitted or not, and says so."""
    from thermolimb.mujoco_export import refitted

    runs, saved = _ur3_saved("J5")
    export = to_dcmotor(saved, Motor(0.1, 1.0, 10.0))
    for e in (export, refitted(saved, export, runs)):
        assert any(n.startswith("its heat gain is nil (betaR_K_per_effort2 = ") for n in e.notes), e.notes
    _, saved = _ur3_saved("J1")
    assert not any("nil" in n for n in to_dcmotor(saved, Motor(0.1, 1.0)).notes)


def test_a_refit_the_log_cannot_make_is_said_beside_the_export(calibration, tmp_path, capsys):
    """A log whose effort never moves cannot refit one node's heat gain: the export goes on and says why; asked
    for with --refit, the same sentence ends it (exit 2)."""
    import pandas as pd

    log, model = calibration
    still = tmp_path / "still.csv"
    frame = pd.read_csv(log)
    frame.assign(effort=0.0).to_csv(still, index=False)
    argv = ["export", str(model), str(still), "--to", "mujoco", "--motor-const", "0.12", "--resistance", "0.8", "--actuator",
            "knee"]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "one node could not be fitted again on the log: cannot identify betaR_K_per_effort2" in err, err
    assert main(argv + ["--refit"]) == 2
    assert "cannot identify betaR_K_per_effort2" in capsys.readouterr().err


def _with_effort_unit(calibration, unit):
    from dataclasses import replace

    saved = ModelFile.load(calibration[1])
    name, model = next(iter(saved.actuators.items()))
    return replace(model, channel_units={**model.channel_units, "effort": unit})


def test_a_model_of_current_is_refused_by_the_wrapper_without_a_torque_constant_and_converted_with_one(calibration):
    """A model fitted on a current in mA heats from 1000 mA per A: the environment's torque (N m) over the torque
    constant (N m/A) is that current; without the constant the wrapper refuses in one sentence naming both units."""
    from thermolimb.util.errors import UsageError

    in_mA = _with_effort_unit(calibration, "mA")
    with pytest.raises(UsageError, match=r"current in mA; AntEnv gives torques in N m: pass torque_constant"):
        ThermalWrapper(gym.make("Ant-v5"), models=in_mA)
    k_t = 2.0  # N m/A
    env = ThermalWrapper(gym.make("Ant-v5"), models=in_mA, torque_constant_Nm_per_A=k_t, observe=None)
    assert env.reader.per_effort == pytest.approx(1000.0 / k_t, rel=0, abs=0)
    in_Nm = ThermalWrapper(gym.make("Ant-v5"), models=_with_effort_unit(calibration, "N m"), observe=None)
    assert in_Nm.reader.per_effort is None
    with pytest.raises(UsageError, match="cannot turn into W"):
        ThermalWrapper(gym.make("Ant-v5"), models=_with_effort_unit(calibration, "W"))


@pytest.mark.parametrize("option, value, words", [
    ("start_C", float("nan"), "start_C must be a finite number"),
    ("limit_C", float("nan"), "limit_C must be a finite number"),
    ("limit_C", -5.0, "8 of 8 joints start at or above their limit"),
    ("penalty", -1.0, "penalty must be a finite number >= 0"),
    ("ambient_C", 1e6, "ambient_C must be a finite number between -60 and 400 degC"),
    ("warning_C", 399.0, "warning_C .* must not lie above limit_C"),
    ("joints", "hip_1", "joints must be a list of joint names"),
])
def test_the_wrapper_refuses_values_out_of_their_range_in_one_sentence(option, value, words):
    from thermolimb.util.errors import UsageError

    with pytest.raises(UsageError, match=words):
        ThermalWrapper(gym.make("Ant-v5"), plant=X8_9, **{option: value})


def test_a_step_before_reset_is_refused_and_a_wrapped_env_runs_in_subprocesses():
    """Gymnasium's own order (reset first), and a wrapped environment that pickles: an asynchronous vector env
    builds it in two worker processes and steps it there, heating as the same env in this process does."""
    import pickle

    env = ThermalWrapper(gym.make("Ant-v5"), plant=X8_9, observe="dict")
    with pytest.raises(gym.error.ResetNeeded, match="reset"):
        env.step(env.action_space.sample())
    pickle.loads(pickle.dumps(env.reader))  # the readers are plain objects

    def make():
        return ThermalWrapper(gym.make("Ant-v5"), plant=X8_9, observe="dict")

    envs = gym.vector.AsyncVectorEnv([make, make], context="spawn")
    try:
        obs, _ = envs.reset(seed=[1, 2])
        actions = np.zeros(envs.action_space.shape)
        obs, _, _, _, info = envs.step(actions)
        assert info["temperature_C"].shape == (2, 8) and np.all(np.isfinite(info["temperature_C"]))
    finally:
        envs.close()


POLICIES = '''
import numpy as np
def raises(env, obs): raise RuntimeError("boom")
def none(env, obs): return None
def short(env, obs): return np.zeros(3)
def nan(env, obs): return np.full(env.action_space.shape, np.nan)
def chatty(env, obs):
    print("hello from the policy")
    return np.zeros(env.action_space.shape)
'''


@pytest.mark.parametrize("argv, said", [
    (["--policy", "userpolicy:raises"], "--policy userpolicy:raises raised RuntimeError at step 0: boom"),
    (["--policy", "userpolicy:none"], "returned None at step 0; expected an action of shape (8,)"),
    (["--policy", "userpolicy:short"], "returned shape (3,) at step 0; expected an action of shape (8,)"),
    (["--policy", "userpolicy:nan"], "returned 8 value(s) that are not finite (NaN or inf) at step 0"),
    (["--env-arg", "frame_skip=0"], "could not be made with frame_skip=0: ZeroDivisionError"),
    (["--env-arg", "xml_file={tmp}/userpolicy.py"], "could not be made with xml_file="),
    (["--env-arg", "render_mode=human"], "render_mode=human: the audit draws no window"),
    (["--env-arg", "healthy_reward=nan"], "failed at step 0: TypeError"),
])
def test_the_user_s_policy_and_environment_arguments_get_one_sentence(tmp_path, monkeypatch, argv, said, capsys):
    (tmp_path / "userpolicy.py").write_text(POLICIES)
    monkeypatch.syspath_prepend(str(tmp_path))
    argv = [a.format(tmp=tmp_path) for a in argv]
    assert main(["audit", "--env", "Ant-v5", "--duration", "0.2", "--plant", "x8-9", *argv]) == 2
    err = capsys.readouterr().err
    assert said in err and len(err.strip().splitlines()) == 1


def test_what_a_policy_prints_goes_to_standard_error_and_the_json_stays_whole(tmp_path, monkeypatch, capsys):
    (tmp_path / "userpolicy.py").write_text(POLICIES)
    monkeypatch.syspath_prepend(str(tmp_path))
    assert main(["audit", "--env", "Ant-v5", "--duration", "0.2", "--plant", "x8-9", "--policy", "userpolicy:chatty",
                 "--json"]) == 0
    out, err = capsys.readouterr()
    assert json.loads(out)["policy"] == "userpolicy:chatty" and "hello from the policy" in err

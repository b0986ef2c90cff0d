"""ROS bags in (ROS 1, ROS 2 SQLite and MCAP), MCAP out, and channels on several time bases aligned."""

import json
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest
from conftest import FIRST_ORDER_X8
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from thermolimb.cli.main import main
from thermolimb.data import WX200_BAG, WX200_EXPORT
from thermolimb.logs import LogError, bags, read_log
from thermolimb.logs.align import align, interval_average
from thermolimb.logs.bag_writer import CONTROL_DEFINITIONS, DYNAMIC_TYPE, INTERFACE_TYPE, write_mcap
from thermolimb.logs.bags import inspect_bag, suggest_mapping
from thermolimb.logs.follow_mcap import McapFollower
from thermolimb.plant import ThermalPlant, run_profile
from thermolimb.plant.profiles import random_holds
from thermolimb.workbench.validation import Scheme, validate_model

BAG = WX200_BAG.paths[0]


# --- the alignment rule ----------------------------------------------------------------------------------------

def test_interval_average_keeps_the_heat_of_a_sinusoid():
    """A 1 Hz sinusoid averaged over 5 s intervals: mean ~ 0, but its square is kept exactly (signed RMS)."""
    t_in = np.arange(0.0, 60.0, 0.01)
    x = 3.0 * np.sin(2 * np.pi * t_in)
    t = np.arange(0.0, 60.0, 5.0)
    rms = interval_average(t, t_in, x, root_mean_square=True)
    mean = interval_average(t, t_in, x, root_mean_square=False)
    assert np.allclose(rms[:-1] ** 2, 4.5, rtol=1e-3)
    assert np.all(np.abs(mean) < 0.05)


def test_interval_average_holds_each_sample_until_the_next_and_weighs_it_by_that_time():
    t = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    t_in = np.array([-0.5, 0.1, 0.5, 2.2, 2.5, 4.0])
    x = np.array([9.0, 1.0, -3.0, 2.0, 2.0, 5.0])
    # [0, 1): 9 held 0.1 s, 1 for 0.4 s, -3 for 0.5 s; [1, 2): -3 held through; [2, 3): -3 for 0.2 s, 2 for 0.8 s
    assert np.allclose(interval_average(t, t_in, x, False), [-0.2, -3.0, 1.0, 2.0, 2.0])
    # nothing in [0, 1): the last value before 0 s is held
    assert np.allclose(interval_average(t, np.array([-1.0, 1.5, 5.0]), np.array([7.0, 8.0, 9.0]), False),
                       [7.0, 7.5, 8.0, 8.0, 8.0])
    # two topics stamped alike but for microseconds of jitter: each interval holds its own sample, whichever side
    # of the temperature's stamp it fell
    stamps = np.arange(0.0, 20.0)
    jitter = np.where(np.arange(20) % 2 == 0, -1e-6, 1e-6)
    effort = np.arange(20.0) ** 2
    assert np.allclose(interval_average(stamps[1:-1], stamps + jitter, effort, False)[:-1], effort[1:-2], atol=1e-3)


def test_align_keeps_the_temperature_samples_and_leaves_out_those_outside_the_inputs():
    t_T = np.arange(0.0, 100.0, 5.0)
    T = 30.0 + 0.1 * t_T
    t_in = np.arange(12.0, 80.0, 0.1)
    out, notes = align((t_T, T), {"effort": (t_in, np.ones_like(t_in))}, "log")
    assert out["time"][0] == 15.0 and out["time"][-1] == 75.0
    assert np.array_equal(out["temperature"], 30.0 + 0.1 * out["time"])  # measured values, not interpolated
    assert "left out" in notes[0]
    with pytest.raises(LogError, match="do not overlap in time"):
        align((t_T, T), {"effort": (t_in + 500.0, t_in)}, "log")


def test_wide_csv_with_its_own_time_column_per_channel(tmp_path):
    t_in = np.arange(0.0, 300.0, 0.1)
    effort = 2.0 * np.sin(2 * np.pi * t_in)
    t_T = np.arange(3.0, 300.0, 5.0)
    frame = pd.DataFrame({"ts": pd.Series(t_in), "tau": pd.Series(effort),
                          "t_temp": pd.Series(t_T), "temp": pd.Series(40.0 + 0.01 * t_T)})
    path = tmp_path / "wide.csv"
    frame.to_csv(path, index=False)
    log = read_log(path, mapping={"effort": "tau@ts", "temperature": "temp@t_temp"}, actuator_name="m")
    s = log.series("m")
    assert np.array_equal(s.time_s, t_T[t_T <= t_in[-1]])
    assert np.allclose(s.signals.effort[:-1] ** 2, 2.0, rtol=0.05)
    with pytest.raises(LogError, match="'missing'"):
        read_log(path, mapping={"effort": "tau@missing", "temperature": "temp@t_temp"})


# --- the real ROS 1 bag and its CSV export -----------------------------------------------------------------------

def test_real_ros1_bag_lists_its_topics_and_suggests_a_mapping():
    infos = {i.topic: i for i in inspect_bag(BAG)}
    assert infos["/wx200/joint_states"].count == 10598
    assert infos["/wx200/temperatures/joint_group"].msgtype == "interbotix_xsarm_diagnostic_tool/msg/JointTemps"
    assert 99.0 < infos["/wx200/joint_states"].rate_hz < 101.0
    mapping, _ = suggest_mapping(list(infos.values()))
    assert mapping == {"effort": "/wx200/joint_states.effort", "temperature": "/wx200/temperatures/joint_group.temps",
                       "velocity": "/wx200/joint_states.velocity"}


def test_a_bag_keeps_the_other_numeric_fields_of_its_mapped_topics_as_extra_channels(plant_run, tmp_path):
    """The servo's joint positions ride along for --discover; fields that never change (a Temperature message's
    variance, the plant's zero positions) carry nothing and are not kept; a field named by the user keeps its name."""
    log = read_log(BAG, actuator_name="waist")
    assert log.extras == ("position",) and any("position=/wx200/joint_states.position" in n for n in log.notes)
    series = log.series("waist")
    assert np.ptp(series.signals.channel("extra.position")) > 0.1  # the waist turns (rad by ROS's convention)
    named = read_log(BAG, mapping="effort=/wx200/joint_states.effort,temperature=/wx200/temperatures/joint_group.temps,"
                                  "extra.angle=/wx200/joint_states.position", actuator_name="waist")
    assert named.extras == ("angle", "velocity")  # the user's name; velocity is no longer mapped, so it is extra
    constant = read_log(write_mcap(plant_run, tmp_path / "run.mcap", layout="per_joint"))
    assert constant.extras == ()


def test_real_bag_agrees_with_its_csv_export():
    """Same temperatures, sample for sample; interval-mean-square effort within a few % (the export keeps 11 Hz of
    the 100 Hz states, and shifts each time base to zero at its own first sample)."""
    bag = WX200_BAG.read()[0].series("waist")
    csv = WX200_EXPORT.read()[0].series("waist")
    assert bag.n == csv.n == 21
    assert np.array_equal(bag.temperature_C, csv.temperature_C)
    heat_bag, heat_csv = np.mean(bag.signals.effort ** 2), np.mean(csv.signals.effort ** 2)
    assert abs(heat_bag / heat_csv - 1.0) < 0.05
    scheme = Scheme.at_split(0.7)
    a, b = (validate_model([s], "joule", scheme) for s in (bag, csv))
    assert abs(a.validation["rmse_K"] - b.validation["rmse_K"]) < 0.3
    assert a.validation["rmse_K"] < 1.0


def test_real_bag_diagnosed_end_to_end(capsys):
    assert main(["diagnose", str(BAG), "--actuator", "waist", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["actuator"] == "waist"
    assert out["base"]["rmse_K"] < 1.0


# --- ROS 2 bags written here and read back ------------------------------------------------------------------------

@pytest.fixture(scope="module")
def plant_run():
    rng = np.random.default_rng(3)
    profile = random_holds(1200.0, 1.0, 2, rng)
    plant = ThermalPlant(["hip", "knee"], [FIRST_ORDER_X8] * 2, rng=rng)
    return run_profile(plant, profile).log


def test_plant_run_round_trips_through_mcap(plant_run, tmp_path):
    path = plant_run.write(tmp_path / "run.mcap")
    back = read_log(path)
    assert back.actuators == plant_run.actuators
    assert any("mapping chosen" in n for n in back.notes)
    for name in plant_run.actuators:
        a, b = plant_run.series(name), back.series(name)
        assert np.allclose(a.time_s - a.time_s[0], b.time_s - b.time_s[0], atol=1e-9)
        assert np.array_equal(a.temperature_C, b.temperature_C)
        assert np.array_equal(a.signals.effort[:-1], b.signals.effort[:-1])
        assert np.array_equal(a.signals.current_A[:-1], b.signals.current_A[:-1])
        assert np.allclose(a.signals.ambient_C[:-1], b.signals.ambient_C[:-1])
    assert not list(tmp_path.glob(".*"))  # nothing temporary left beside it


def test_plant_run_in_the_per_joint_layout_reads_back_by_the_suggested_pattern(plant_run, tmp_path):
    """One sensor_msgs/Temperature topic per joint, every fifth sample: read with the {j} pattern the reader
    suggests, each joint gets its own temperatures at their own stamps."""
    path = write_mcap(plant_run, tmp_path / "run.mcap", layout="per_joint", temperature_every=5)
    back = read_log(path)
    assert back.actuators == plant_run.actuators
    assert any("/{j}/temperature.temperature" in n for n in back.notes)
    for name in plant_run.actuators:
        a, b = plant_run.series(name), back.series(name)
        assert np.array_equal(b.temperature_C, a.temperature_C[::5][:b.n])
        assert b.n >= a.n // 5 - 1


def test_a_ros2_control_recording_is_read_from_its_dynamic_joint_states(plant_run, tmp_path):
    """ros2_control's joint state broadcaster publishes a hardware's state interfaces per joint on
    /dynamic_joint_states (control_msgs/DynamicJointState, its definition stored in the MCAP): inspect suggests the
    temperature there, the current beside it, and every joint reads back its own, at their own stamps."""
    path = write_mcap(plant_run, tmp_path / "run.mcap", layout="ros2_control", temperature_every=2)
    mapping, reasons = suggest_mapping(inspect_bag(path))
    assert not reasons and mapping == {"effort": "/joint_states.effort", "velocity": "/joint_states.velocity",
                                       "temperature": "/dynamic_joint_states.temperature",
                                       "current": "/dynamic_joint_states.current", "ambient": "/ambient.temperature"}
    back = read_log(path)
    assert back.actuators == plant_run.actuators
    for name in plant_run.actuators:
        a, b = plant_run.series(name), back.series(name)
        assert np.array_equal(b.temperature_C, a.temperature_C[::2][:b.n]) and b.n >= a.n // 2 - 1
        assert np.array_equal(b.signals.current_A[:-1], a.signals.current_A[::2][:b.n - 1])  # one value an interval
        assert set(b.signals.extra) <= {"joint_states_position", "dynamic_joint_states_position"}  # no effort again
    assert main(["fit", str(path), "--actuator", "knee", "--quiet"]) == 0


def _control_bag(folder, times):
    """A ROS 2 bag of /dynamic_joint_states alone, as a user records it: hip and knee with their interfaces
    (position, velocity, effort, the motor's temperature and the driver's FETs'), a gripper with position and
    effort only."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    for msgtype, definition in CONTROL_DEFINITIONS.items():
        store.register(get_types_from_msg(definition, msgtype))
    Dynamic, Interface, Header, Time = (store.types[k] for k in (DYNAMIC_TYPE, INTERFACE_TYPE, "std_msgs/msg/Header",
                                                                 "builtin_interfaces/msg/Time"))
    joint = ["position", "velocity", "effort", "motor_temperature", "fet_temperature"]
    with Writer(folder, version=8, storage_plugin=StoragePlugin.MCAP) as w:
        conn = w.add_connection("/dynamic_joint_states", DYNAMIC_TYPE, typestore=store)
        for t in times:
            ns = int(t * 1e9) + 10**18
            values = [Interface(interface_names=joint, values=np.array([0.0, 0.5, 2.0, 30.0 + 0.01 * t, 40.0])),
                      Interface(interface_names=joint, values=np.array([0.0, 0.0, 3.0, 31.0 + 0.02 * t, 41.0])),
                      Interface(interface_names=["position", "effort"], values=np.array([0.01, 0.2]))]
            msg = Dynamic(header=Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id=""),
                          joint_names=["hip", "knee", "gripper"], interface_values=values)
            w.write(conn, ns, store.serialize_cdr(msg, DYNAMIC_TYPE))
    return folder


def test_dynamic_joint_states_alone_give_the_motor_s_temperature_and_leave_out_a_joint_without_one(tmp_path):
    """Recorded without /joint_states, the effort comes from the interfaces too; of two temperatures the motor's
    is taken (the FETs' comes along as an extra channel), and a gripper with no temperature interface is not an
    actuator of the fleet rather than a reason to refuse it."""
    folder = _control_bag(tmp_path / "bag", np.arange(0.0, 300.0, 0.5))
    mapping, reasons = suggest_mapping(inspect_bag(folder))
    assert not reasons and mapping == {"effort": "/dynamic_joint_states.effort",
                                       "velocity": "/dynamic_joint_states.velocity",
                                       "temperature": "/dynamic_joint_states.motor_temperature"}
    log = read_log(folder)
    assert log.actuators == ("hip", "knee")
    knee = log.series("knee")
    assert np.allclose(knee.temperature_C, 31.0 + 0.02 * knee.time_s) and np.allclose(knee.signals.effort, 3.0)
    assert np.allclose(knee.signals.extra["fet_temperature"], 41.0)
    with pytest.raises(LogError, match="no field 'temp'; its numeric fields are position, velocity, effort"):
        read_log(folder, mapping={"effort": "/dynamic_joint_states.effort",
                                  "temperature": "/dynamic_joint_states.temp"})


MOTOR_STATE = """uint8 mode
float32 q
float32 dq
float32 ddq
float32 tau_est
float32 q_raw
float32 dq_raw
float32 ddq_raw
int8 temperature
uint32 lost
uint32[2] reserve
"""
LOW_STATE = """uint8 level_flag
unitree_go/MotorState[4] motor_state
int8 temperature_ntc1
float32 power_v
uint32 tick
"""


def test_a_unitree_low_state_reads_each_motor_of_its_motor_state_array(plant_run, tmp_path, capsys):
    """A Unitree robot's /lowstate (unitree_go/LowState, its definition stored in the MCAP): an array of MotorState
    sub-messages, one per motor slot, with no joint names.  Its fields read across the array, the motors numbered
    from 0; inspect suggests the motor's temperature (not the board's temperature_ntc1), the estimated torque and
    the filtered speed (dq, not dq_raw); and the slots nothing drives are said to be so by fit."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    for msgtype, definition in (("unitree_go/msg/MotorState", MOTOR_STATE), ("unitree_go/msg/LowState", LOW_STATE)):
        store.register(get_types_from_msg(definition, msgtype))
    Low, Motor = store.types["unitree_go/msg/LowState"], store.types["unitree_go/msg/MotorState"]
    series = [plant_run.series(name) for name in plant_run.actuators]
    with Writer(tmp_path / "bag", version=8, storage_plugin=StoragePlugin.MCAP) as w:
        conn = w.add_connection("/lowstate", Low.__msgtype__, typestore=store)
        for k, t in enumerate(series[0].time_s):
            motors = [Motor(mode=1, q=0.0, dq=s.signals.velocity[k], ddq=0.0, tau_est=s.signals.effort[k], q_raw=0.0,
                            dq_raw=s.signals.velocity[k] + 0.3, ddq_raw=0.0, temperature=int(s.temperature_C[k]),
                            lost=0, reserve=np.zeros(2, np.uint32)) for s in series]
            motors += [Motor(mode=0, q=0.0, dq=0.0, ddq=0.0, tau_est=0.0, q_raw=0.0, dq_raw=0.0, ddq_raw=0.0,
                             temperature=0, lost=0, reserve=np.zeros(2, np.uint32)) for _ in range(4 - len(series))]
            msg = Low(level_flag=255, motor_state=motors, temperature_ntc1=40, power_v=24.0, tick=k)
            w.write(conn, int(t * 1e9) + 10**18, store.serialize_cdr(msg, Low.__msgtype__))
    folder = tmp_path / "bag"
    (info,) = inspect_bag(folder)
    assert info.joint_names == ("0", "1", "2", "3") and "motor_state.tau_est" in info.numeric_fields
    mapping, reasons = suggest_mapping([info])
    assert not reasons and mapping == {"temperature": "/lowstate.motor_state.temperature",
                                       "effort": "/lowstate.motor_state.tau_est",
                                       "velocity": "/lowstate.motor_state.dq"}
    log = read_log(folder)
    assert log.actuators == ("0", "1", "2", "3")
    for k, s in enumerate(series):
        back = log.series(str(k))
        assert np.array_equal(back.temperature_C, np.floor(s.temperature_C)[:back.n])  # whole degrees, as sent
        assert np.allclose(back.signals.effort[:-1], s.signals.effort[:back.n - 1], rtol=1e-6, atol=1e-5)
    assert main(["fit", str(folder), "--actuator", "1", "--quiet"]) == 0
    for field, said in (("motor_state.temp", "LowState\\) has no field 'motor_state.temp'; its numeric fields are "
                                              "level_flag, motor_state.mode"),
                        ("motor_state.reserve", "holds several numbers in each element of motor_state")):
        with pytest.raises(LogError, match=said):
            read_log(folder, mapping={"effort": "/lowstate.motor_state.tau_est", "temperature": f"/lowstate.{field}"})
    assert main(["fit", str(folder), "--actuator", "3", "--quiet"]) == 2  # an empty slot: said, not fitted
    capsys.readouterr()
    assert main(["fit", str(folder), "--fleet", "--quiet", "--workers", "1", "--backend", "serial"]) == 0
    rows = capsys.readouterr().out.splitlines()
    assert [r.split()[0] for r in rows if "a motor that is not connected" in r] == ["2", "3"]


def test_an_array_of_motor_states_each_naming_its_motor_reads_each_by_its_name(plant_run, tmp_path):
    """A servo driver's list of motor states (each element with its own name, speed, load and temperature, as
    Dynamixel drivers publish them; no JointState): the motors are named by their elements, the load stands for the
    effort and the speed for the velocity."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    definitions = {"servo_msgs/msg/MotorState": "string name\nfloat64 position\nfloat64 speed\nfloat64 load\n"
                                                "float64 voltage\nint32 temperature\n",
                   "servo_msgs/msg/MotorStateList": "servo_msgs/MotorState[] motor_states\n"}
    for msgtype, definition in definitions.items():
        store.register(get_types_from_msg(definition, msgtype))
    State, List = store.types["servo_msgs/msg/MotorState"], store.types["servo_msgs/msg/MotorStateList"]
    series = {name: plant_run.series(name) for name in plant_run.actuators}
    with Writer(tmp_path / "bag", version=8, storage_plugin=StoragePlugin.MCAP) as w:
        conn = w.add_connection("/motor_states", List.__msgtype__, typestore=store)
        for k, t in enumerate(series["hip"].time_s):
            states = [State(name=n, position=0.0, speed=s.signals.velocity[k], load=s.signals.effort[k], voltage=12.0,
                            temperature=int(s.temperature_C[k])) for n, s in series.items()]
            w.write(conn, int(t * 1e9) + 10**18, store.serialize_cdr(List(motor_states=states), List.__msgtype__))
    mapping, reasons = suggest_mapping(inspect_bag(tmp_path / "bag"))
    assert not reasons and mapping == {"temperature": "/motor_states.motor_states.temperature",
                                       "effort": "/motor_states.motor_states.load",
                                       "velocity": "/motor_states.motor_states.speed"}
    log = read_log(tmp_path / "bag")
    assert log.actuators == plant_run.actuators
    knee = log.series("knee")
    assert np.array_equal(knee.temperature_C, np.floor(series["knee"].temperature_C)[:knee.n])


def _beside_joint_states(run, folder, store, topic: str, msgtype: str, message, each=None) -> list:
    """An MCAP bag of ``run``'s JointState and, 1 us after each, ``message(k, series)`` on ``topic`` (and with
    ``each``, ``each(k, s)`` of the same type on ``/<joint>/motor_temp``): the series."""
    JointState, Header, Time = (store.types[k] for k in
                                ("sensor_msgs/msg/JointState", "std_msgs/msg/Header", "builtin_interfaces/msg/Time"))
    series = [run.series(name) for name in run.actuators]
    with Writer(folder, version=8, storage_plugin=StoragePlugin.MCAP) as w:
        states = w.add_connection("/joint_states", JointState.__msgtype__, typestore=store)
        other = w.add_connection(topic, msgtype, typestore=store)
        joints = [w.add_connection(f"/{s.actuator}/motor_temp", msgtype, typestore=store) for s in series] if each \
            else []
        for k, t in enumerate(series[0].time_s):
            ns = int(t * 1e9) + 10**18
            header = Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="")
            state = JointState(header=header, name=list(run.actuators), position=np.zeros(len(series)),
                               velocity=np.array([s.signals.velocity[k] for s in series]),
                               effort=np.array([s.signals.effort[k] for s in series]))
            w.write(states, ns, store.serialize_cdr(state, JointState.__msgtype__))
            w.write(other, ns + 1000, store.serialize_cdr(message(k, series), msgtype))
            for conn, s in zip(joints, series):
                w.write(conn, ns + 2000, store.serialize_cdr(each(k, s), msgtype))
    return series


def test_temperatures_in_an_array_without_joint_names_read_in_the_joint_states_order(plant_run, tmp_path):
    """Temperatures published as a std_msgs/Float64MultiArray (no joint names) beside a JointState: inspect suggests
    the array, and its values are read in the order the JointState names the joints, which a note says."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    Array, Layout = store.types["std_msgs/msg/Float64MultiArray"], store.types["std_msgs/msg/MultiArrayLayout"]
    series = _beside_joint_states(plant_run, tmp_path / "bag", store, "/motor_temperatures", Array.__msgtype__,
                                  lambda k, series: Array(layout=Layout(dim=[], data_offset=0),
                                                          data=np.array([s.temperature_C[k] for s in series])))
    mapping, reasons = suggest_mapping(inspect_bag(tmp_path / "bag"))
    assert not reasons and mapping["temperature"] == "/motor_temperatures.data"
    log = read_log(tmp_path / "bag")
    assert log.actuators == plant_run.actuators
    assert any("/motor_temperatures names no joints: its 2 values are read in the order /joint_states names them "
               "(hip, knee)" in n for n in log.notes)
    for s in series:
        assert np.array_equal(log.series(s.actuator).temperature_C, s.temperature_C[:log.series(s.actuator).n])
    follower = McapFollower(tmp_path / "bag", "effort=/joint_states.effort,temperature=/motor_temperatures.data")
    pieces = follower.poll(final=True)  # followed live alike
    for s in series:
        assert np.array_equal(np.concatenate([p.arrays["temperature"] for p in pieces[s.actuator]]), s.temperature_C)
    assert any("read in the order the efforts name them (hip, knee)" in n for n in follower.notes)
    array = Array(layout=Layout(dim=[], data_offset=0), data=np.array([30.0, 31.0]))  # beside three named joints
    with pytest.raises(LogError, match="names no joints and holds 2 values a message, where the efforts name 3"):
        follower.mapping["temperature"].in_order(array, "/motor_temperatures", "live.mcap", ["a", "b", "c"], [])
    empty = Array(layout=Layout(dim=[], data_offset=0), data=np.zeros(0))  # a publisher with nothing for them
    assert follower.mapping["temperature"].in_order(empty, "/motor_temperatures", "live.mcap", ["a", "b"], []) == {}


def test_a_feedback_array_that_names_no_joints_reads_in_the_joint_states_order(plant_run, tmp_path):
    """An arm's cyclic feedback (a Kinova's base_feedback: an array of actuator feedbacks, no names, each with the
    motor's and the core's temperatures) beside a JointState: the motor's temperature is suggested, and read in
    the order the JointState names the joints (said)."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    definitions = {"arm_msgs/msg/ActuatorFeedback": "float32 position\nfloat32 velocity\nfloat32 torque\n"
                                                    "float32 current_motor\nfloat32 temperature_motor\n"
                                                    "float32 temperature_core\n",
                   "arm_msgs/msg/Feedback": "arm_msgs/ActuatorFeedback[] actuators\n"}
    for msgtype, definition in definitions.items():
        store.register(get_types_from_msg(definition, msgtype))
    Actuator, Feedback = store.types["arm_msgs/msg/ActuatorFeedback"], store.types["arm_msgs/msg/Feedback"]
    series = _beside_joint_states(plant_run, tmp_path / "bag", store, "/base_feedback", Feedback.__msgtype__,
                                  lambda k, series: Feedback(actuators=[
                                      Actuator(position=0.0, velocity=s.signals.velocity[k], torque=s.signals.effort[k],
                                               current_motor=0.0, temperature_motor=s.temperature_C[k],
                                               temperature_core=40.0) for s in series]))
    mapping, reasons = suggest_mapping(inspect_bag(tmp_path / "bag"))
    assert not reasons and mapping["effort"] == "/joint_states.effort"
    assert mapping["temperature"] == "/base_feedback.actuators.temperature_motor"
    log = read_log(tmp_path / "bag", mapping=mapping)
    assert log.actuators == plant_run.actuators
    assert any("/base_feedback names no joints: its 2 values are read in the order /joint_states names them" in n
               for n in log.notes)
    knee = log.series("knee")
    assert np.allclose(knee.temperature_C, series[1].temperature_C[:knee.n], atol=1e-5)  # float32 on the wire
    # beside a JointState that names a gripper too, which value is whose cannot be told: said, not guessed
    wanted = {"effort": ("/joint_states", "effort"), "temperature": ("/base_feedback", "actuators.temperature_motor")}
    data = {"effort": ([0.0], [np.zeros(3)], [("hip", "knee", "finger")]), "temperature": ([0.0], [np.zeros(2)], [()])}
    with pytest.raises(LogError, match="names no joints and holds 2 values a message, where /joint_states names 3"):
        bags._in_joint_order(wanted, data, tmp_path / "bag", [])


def test_a_plain_number_per_joint_named_for_its_temperature_reads_as_a_temperature_topic(plant_run, tmp_path):
    """Temperatures as a std_msgs/Float64 per joint (``/hip/motor_temp``), the air as another (``/ambient_temp``),
    beside a JointState: suggested and read as per-joint Temperature topics are."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    Number = store.types["std_msgs/msg/Float64"]
    series = _beside_joint_states(plant_run, tmp_path / "bag", store, "/ambient_temp", Number.__msgtype__,
                                  lambda k, series: Number(data=25.0),
                                  each=lambda k, s: Number(data=float(s.temperature_C[k])))
    mapping, reasons = suggest_mapping(inspect_bag(tmp_path / "bag"))
    assert not reasons and mapping["temperature"] == "/{j}/motor_temp.data"
    assert mapping["ambient"] == "/ambient_temp.data"
    log = read_log(tmp_path / "bag")
    assert log.actuators == plant_run.actuators
    for s in series:
        assert np.array_equal(log.series(s.actuator).temperature_C, s.temperature_C[:log.series(s.actuator).n])


def test_a_driver_s_diagnostics_read_each_joint_s_temperature_from_its_status(plant_run, tmp_path):
    """Temperatures reported on /diagnostics (diagnostic_msgs/DiagnosticArray: per status, key-value strings), a
    status per joint named around the joint's name, and one that is no joint's: the motor's key is suggested, each
    status read as its joint's (said), strings that are no number skipped."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    Array, Status, KeyValue = (store.types[f"diagnostic_msgs/msg/{k}"] for k in
                               ("DiagnosticArray", "DiagnosticStatus", "KeyValue"))
    Header, Time = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]

    def diagnostics(k, series):
        statuses = [Status(level=0, name=f"Joint {s.actuator}: motor driver", message="OK", hardware_id="can0",
                           values=[KeyValue(key="Motor temperature", value=f"{s.temperature_C[k]:.6f}"),
                                   KeyValue(key="Board temperature", value="41.5"),
                                   KeyValue(key="Mode", value="POSITION")]) for s in series]
        statuses.append(Status(level=0, name="Battery", message="OK", hardware_id="bms",
                               values=[KeyValue(key="Voltage", value="24.1")]))
        return Array(header=Header(stamp=Time(sec=0, nanosec=0), frame_id=""), status=statuses)

    series = _beside_joint_states(plant_run, tmp_path / "bag", store, "/diagnostics", Array.__msgtype__, diagnostics)
    (info,) = [i for i in inspect_bag(tmp_path / "bag") if i.topic == "/diagnostics"]
    assert set(info.numeric_fields) == {"Motor_temperature", "Board_temperature", "Voltage"}
    mapping, reasons = suggest_mapping(inspect_bag(tmp_path / "bag"))
    assert not reasons and mapping["temperature"] == "/diagnostics.Motor_temperature"
    log = read_log(tmp_path / "bag")
    assert log.actuators == plant_run.actuators
    assert any("'Joint hip: motor driver' as hip" in n for n in log.notes)
    for s in series:
        back = log.series(s.actuator)
        assert np.allclose(back.temperature_C, s.temperature_C[:back.n], atol=1e-6)
        assert not back.signals.extra  # the diagnostics' other keys are not offered as channels
    pieces = McapFollower(tmp_path / "bag", "effort=/joint_states.effort,temperature=/diagnostics.Motor_temperature"
                          ).poll(final=True)  # followed live alike
    for s in series:
        assert np.allclose(np.concatenate([p.arrays["temperature"] for p in pieces[s.actuator]]), s.temperature_C,
                           atol=1e-6)


def _sqlite_bag(folder, t_states, t_temps, joint="knee", temperature_joints=None, topic="/{j}/temperature",
                shuffled=False, grippers=False):
    """A ROS 2 SQLite bag: JointState for two joints, and a scalar sensor_msgs/Temperature topic for ``joint`` (or
    one per joint of ``temperature_joints``, the common per-joint layout, named by ``topic``).  ``shuffled``: the
    joints named in another order every other message; ``grippers``: a second publisher on the JointState topic,
    a gripper's position alone (no effort, no velocity), between the joints' messages."""
    store = get_typestore(Stores.ROS2_HUMBLE)
    JointState, Header, Time = (store.types[k] for k in
                                ("sensor_msgs/msg/JointState", "std_msgs/msg/Header", "builtin_interfaces/msg/Time"))
    Temperature = store.types["sensor_msgs/msg/Temperature"]
    with Writer(folder, version=8, storage_plugin=StoragePlugin.SQLITE3) as w:
        states = w.add_connection("/joint_states", JointState.__msgtype__, typestore=store)
        temps = {j: w.add_connection(topic.format(j=j), Temperature.__msgtype__, typestore=store)
                 for j in (temperature_joints or [joint])}
        for k, t in enumerate(t_states):
            ns = int(t * 1e9) + 10**18
            h = Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="")
            order = [1, 0] if shuffled and k % 2 else [0, 1]
            names, effort = np.array(["hip", joint]), np.array([1.0, 3.0 + np.sin(np.pi * t)])
            msg = JointState(header=h, name=list(names[order]), position=np.zeros(2), velocity=np.zeros(2),
                             effort=effort[order])
            w.write(states, ns, store.serialize_cdr(msg, JointState.__msgtype__))
            if grippers:
                msg = JointState(header=h, name=["gripper"], position=np.zeros(1), velocity=np.zeros(0),
                                 effort=np.zeros(0))
                w.write(states, ns + 1000, store.serialize_cdr(msg, JointState.__msgtype__))
        for t in t_temps:
            ns = int(t * 1e9) + 10**18
            h = Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="")
            for k, conn in enumerate(temps.values()):
                msg = Temperature(header=h, temperature=30.0 + 0.01 * (k + 1) * t, variance=0.0)
                w.write(conn, ns, store.serialize_cdr(msg, Temperature.__msgtype__))
    return folder


def test_one_temperature_topic_per_joint_reads_with_a_joint_pattern_and_is_suggested(tmp_path):
    """The common ROS 2 layout: one sensor_msgs/Temperature topic per joint.  {j} in a topic runs over the joint
    names of the JointState topic; inspect suggests it; a fleet reads every joint of the bag in one command."""
    folder = _sqlite_bag(tmp_path / "bag", np.arange(0.0, 200.0, 0.05), np.arange(1.0, 200.0, 2.0),
                         temperature_joints=["hip", "knee"])
    mapping, reasons = suggest_mapping(inspect_bag(folder))
    assert mapping["temperature"] == "/{j}/temperature.temperature" and not reasons
    log = read_log(folder, mapping={"effort": "/joint_states.effort", "temperature": "/{j}/temperature.temperature"})
    assert log.actuators == ("hip", "knee")
    assert np.allclose(log.series("knee").temperature_C, 30.0 + 0.02 * log.series("knee").time_s, atol=0.05)
    assert np.allclose(log.series("hip").signals.effort, 1.0)
    assert read_log(folder).actuators == ("hip", "knee")  # the suggestion, chosen when no --map is given
    assert read_log(folder, actuator_name="knee").actuators == ("knee",)
    # a topic whose name holds "air" inside a word is a joint's; "air" or "room" as words name the ambient
    topics = {"/knee/temperature": "/repair/temperature", "/hip/temperature": "/room/air_temperature"}
    mapping, _ = suggest_mapping([replace(i, topic=topics.get(i.topic, i.topic)) for i in inspect_bag(folder)])
    assert mapping["temperature"] == "/repair/temperature.temperature"
    assert mapping["ambient"] == "/room/air_temperature.temperature"
    assert main(["fit", str(folder), "--fleet", "--quiet", "--workers", "1", "--backend", "serial"]) == 0


def test_joint_topics_named_inside_a_word_joints_in_any_order_and_a_second_publisher_read_as_one(tmp_path):
    """Per-joint temperature topics whose name holds the joint inside a word (``/motors/knee_motor/temperature``)
    are suggested as a pattern; a JointState topic that names its joints in another order from message to message,
    and carries a gripper's position-only messages between, reads every joint's own effort."""
    folder = _sqlite_bag(tmp_path / "bag", np.arange(0.0, 200.0, 0.05), np.arange(1.0, 200.0, 2.0),
                         temperature_joints=["hip", "knee"], topic="/motors/{j}_motor/temperature", shuffled=True,
                         grippers=True)
    mapping, reasons = suggest_mapping(inspect_bag(folder))
    assert mapping["temperature"] == "/motors/{j}_motor/temperature.temperature" and not reasons
    log = read_log(folder, mapping=mapping)
    assert log.actuators == ("hip", "knee")
    assert np.allclose(log.series("hip").signals.effort, 1.0)
    knee = log.series("knee")
    assert np.allclose(knee.signals.effort[:-1] ** 2, 9.0 + 0.5, rtol=1e-3)  # 3 + sin: its mean square over 2 s
    assert np.allclose(knee.temperature_C, 30.0 + 0.02 * knee.time_s, atol=0.05)
    joints = ("left_knee", "knee")  # the longest name a topic holds is its joint's
    assert bags._joint_topic_pattern(["/t/left_knee/temp", "/t/knee/temp"], joints) == "/t/{j}/temp"


def test_ros2_sqlite_bag_with_a_scalar_temperature_topic(tmp_path):
    folder = _sqlite_bag(tmp_path / "bag", np.arange(0.0, 200.0, 0.05), np.arange(1.0, 200.0, 2.0))
    mapping = {"effort": "/joint_states.effort", "temperature": "/knee/temperature.temperature"}
    log = read_log(folder, mapping=mapping, actuator_name="knee")
    s = log.series("knee")
    assert s.n == 100
    assert np.all(np.abs(s.signals.effort - np.sqrt(9.5)) < 0.2)  # RMS of 3 + sin(pi t) over its 2 s period
    assert read_log(next(folder.glob("*.db3")), mapping=mapping, actuator_name="knee").series("knee").n == 100
    with pytest.raises(LogError, match="joint 'ankle' is not in /joint_states; its messages name hip, knee"):
        read_log(folder, mapping=mapping, actuator_name="ankle")
    with pytest.raises(LogError, match="one value per message"):
        read_log(folder, mapping=mapping)


@pytest.mark.parametrize("mapping, actuator, expected", [
    ({"effort": "/joint_states.effort", "temperature": "/hip/temperature.temperature"}, "knee",
     "names topic /hip/temperature, which the bag does not have; its topics are /joint_states"),
    ({"effort": "/joint_states.effort", "temperature": "/knee/temperature.temp"}, "knee",
     "(sensor_msgs/msg/Temperature) has no field 'temp'; its numeric fields are temperature, variance"),
    ({"effort": "/knee/temperature.temperature", "temperature": "/joint_states.name"}, "knee",
     "holds list values, not numbers"),
    ({"effort": "joint_states", "temperature": "/knee/temperature.temperature"}, "knee",
     "--map effort=joint_states is not of the form /topic.field"),
])
def test_bad_bag_mappings_say_what_is_wrong(tmp_path, mapping, actuator, expected):
    folder = _sqlite_bag(tmp_path / "bag", np.arange(0.0, 50.0, 0.1), np.arange(1.0, 50.0, 2.0))
    with pytest.raises(LogError) as err:
        read_log(folder, mapping=mapping, actuator_name=actuator)
    assert expected in str(err.value) and str(folder) in str(err.value)


def test_bag_whose_time_bases_do_not_overlap(tmp_path):
    folder = _sqlite_bag(tmp_path / "bag", np.arange(0.0, 50.0, 0.1), np.arange(100.0, 150.0, 2.0))
    with pytest.raises(LogError, match="do not overlap in time"):
        read_log(folder, mapping={"effort": "/joint_states.effort", "temperature": "/knee/temperature.temperature"},
                 actuator_name="knee")


def test_truncated_or_missing_bags_exit_2_with_one_sentence(tmp_path, capsys):
    truncated = tmp_path / "cut.bag"
    truncated.write_bytes(BAG.read_bytes()[:100_000])
    assert main(["fit", str(truncated)]) == 2
    assert "the bag ends before its index, at byte 100000" in capsys.readouterr().err  # the real reason
    junk = tmp_path / "junk.mcap"
    junk.write_bytes(b"not a bag at all" * 100)
    assert main(["diagnose", str(junk)]) == 2
    err = capsys.readouterr().err
    assert "junk.mcap" in err and len(err.strip().splitlines()) == 1
    assert main(["inspect", str(tmp_path / "none.bag")]) == 2
    assert "no such file" in capsys.readouterr().err


def test_inspect_prints_topics_and_the_suggested_map(capsys):
    assert main(["inspect", str(BAG)]) == 0
    out = capsys.readouterr().out
    assert "/wx200/temperatures/joint_group" in out and "suggested: --map effort=/wx200/joint_states.effort" in out


def test_a_schemaless_or_cut_off_mcap_is_said_for_what_it_is(tmp_path, capsys):
    from mcap.writer import CompressionType, Writer

    from thermolimb.cli.main import main

    path = tmp_path / "schemaless.mcap"
    with open(path, "wb") as f:
        w = Writer(f, compression=CompressionType.NONE)
        w.start("ros2", "test")
        channel = w.register_channel("/joint_states", "cdr", 0)  # no schema
        for k in range(50):
            w.add_message(channel, k * 10**9, b"\x00\x01\x00\x00", k * 10**9)
        w.finish()
    assert main(["fit", str(path), "--quiet"]) == 2
    assert "no message schema (a schemaless MCAP)" in capsys.readouterr().err
    whole = tmp_path / "whole.mcap"
    assert main(["simulate", "--duration", "600", "--dt", "1", "--out", str(whole), "--quiet"]) == 0
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(whole.read_bytes()[: whole.stat().st_size // 2])
    assert main(["fit", str(cut), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "ends before its summary" in err and len(err.strip().splitlines()) == 1


def test_a_recording_cut_off_by_a_crash_is_read_to_its_last_complete_chunk(tmp_path, capsys):
    import numpy as np
    from mcap.writer import CompressionType, Writer
    from rosbags.typesys import Stores, get_typestore

    from thermolimb.logs import read_log

    store = get_typestore(Stores.ROS2_HUMBLE)
    JS, TM = store.types["sensor_msgs/msg/JointState"], store.types["sensor_msgs/msg/Temperature"]
    H, T = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
    path = tmp_path / "crash.mcap"
    with open(path, "wb") as f:
        w = Writer(f, chunk_size=4096, compression=CompressionType.NONE)
        w.start("ros2", "test")
        ids = {}
        for topic, cls in (("/joint_states", JS), ("/knee/temperature", TM)):
            schema = w.register_schema(cls.__msgtype__, "ros2msg", store.generate_msgdef(cls.__msgtype__)[0].encode())
            ids[topic] = w.register_channel(topic, "cdr", schema)
        temperature = 30.0
        for k in range(2000):
            ns = int(1.7e18) + k * 10**9
            header = H(stamp=T(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="")
            effort = 5.0 + 4.0 * np.sign(np.sin(k / 120))
            temperature += (25 + 0.3 * effort**2 - temperature) / 150
            w.add_message(ids["/joint_states"], ns, store.serialize_cdr(JS(
                header=header, name=["knee"], position=np.zeros(1), velocity=np.zeros(1), effort=np.array([effort])),
                JS.__msgtype__), ns)
            w.add_message(ids["/knee/temperature"], ns, store.serialize_cdr(TM(
                header=header, temperature=round(temperature, 2), variance=0.0), TM.__msgtype__), ns)
        w.finish()
    data = path.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: int(0.6 * len(data))])
    log = read_log(cut, mapping={"effort": "/joint_states.effort", "temperature": "/{j}/temperature.temperature"})
    assert any("ends before its summary" in n and "read up to its last complete chunk" in n for n in log.notes)
    series = log.series("knee")
    assert 900 < series.n < 1300  # about 60 % of the 2000 samples: the chunks written before the cut


def test_a_ros1_bag_cut_off_by_a_crash_is_read_to_its_last_complete_chunk(tmp_path):
    import numpy as np
    from rosbags.rosbag1 import Writer
    from rosbags.typesys import Stores, get_typestore

    from thermolimb.logs import read_log

    store = get_typestore(Stores.ROS1_NOETIC)
    JS, TM = store.types["sensor_msgs/msg/JointState"], store.types["sensor_msgs/msg/Temperature"]
    H, T = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
    whole = tmp_path / "whole.bag"
    writer = Writer(whole)
    writer.chunk_threshold = 4096  # a recorder's chunks, small
    writer.open()
    joint = writer.add_connection("/joint_states", JS.__msgtype__, typestore=store)
    reading = writer.add_connection("/knee/temperature", TM.__msgtype__, typestore=store)
    temperature = 30.0
    for k in range(2000):
        ns = int(1.7e18) + k * 10**9
        header = H(seq=k, stamp=T(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="")
        effort = 5.0 + 4.0 * np.sign(np.sin(k / 120))
        temperature += (25 + 0.3 * effort**2 - temperature) / 150
        writer.write(joint, ns, store.serialize_ros1(JS(header=header, name=["knee"], position=np.zeros(1),
                                                        velocity=np.zeros(1), effort=np.array([effort])),
                                                     JS.__msgtype__))
        writer.write(reading, ns, store.serialize_ros1(TM(header=header, temperature=round(temperature, 2),
                                                          variance=0.0), TM.__msgtype__))
    writer.close()
    cut = tmp_path / "cut.bag"
    cut.write_bytes(whole.read_bytes()[: int(0.6 * whole.stat().st_size)])
    log = read_log(cut, mapping={"effort": "/joint_states.effort", "temperature": "/{j}/temperature.temperature"})
    assert any("ends before its index" in n and "read up to its last complete chunk" in n for n in log.notes)
    assert 900 < log.series("knee").n < 1300

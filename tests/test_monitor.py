"""The monitor: a model run in pieces carries on exactly; following a CSV another process appends to writes an
MCAP of ROS 2 messages that rosbags reads back; Foxglove's server speaks to a real WebSocket client."""

import json
import re
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np
import pytest
from monitor_logs import model_and_run

from thermolimb.cli.main import main
from thermolimb.logs.follow import CsvFollower
from thermolimb.model import Signals, ThermalModel, model_parameters
from thermolimb.model.reach import first_order_reach_s
from thermolimb.model.saved import ModelFile
from thermolimb.monitor import Session
from thermolimb.monitor.layout import SHIPPED_ACTUATORS, layout_text

TERMS = ("joule", "effort_bias", "second_node", "third_node", "sensor_lag", "speed_losses")
WRITER = """
import sys, time
src, dst, every, pause = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
lines = open(src).read().splitlines(True)
with open(dst, "w") as f:
    f.write(lines[0])
    for i, line in enumerate(lines[1:]):
        f.write(line)
        if i % every == 0:
            f.flush()
            time.sleep(pause)
"""


def test_a_run_in_pieces_carries_on_exactly():
    params = {p.name: p.typical for p in model_parameters(TERMS)}
    params.update(frame_fraction=0.4, body_fraction=0.3, RC_s=40.0)
    model = ThermalModel(TERMS, params)
    rng = np.random.default_rng(1)
    n = 2000
    s = Signals(np.arange(n) * 0.5, rng.uniform(0, 10, n), rng.uniform(0, 3, n))
    whole = model.simulate(s, 30.0, initial_rate_K_per_s=0.01)
    state, keep, parts = None, {}, []
    for lo, hi in zip([0, 5, 700, 701, 1500], [5, 700, 701, 1500, n - 1]):
        out = model.simulate(s.slice(lo, hi + 1), 30.0, initial_rate_K_per_s=0.01, state=state, keep=keep)
        parts.append(out if not parts else out[1:])
        state = dict(keep)
    assert np.max(np.abs(np.concatenate(parts) - whole)) < 1e-9
    assert {"winding", "output", "second_node", "third_node"} <= set(state)


CASCADES = (("joule", "effort_bias"), ("joule", "effort_bias", "winding_tempco"),  # Jorgensen et al.'s, copper
            ("joule", "effort_bias", "speed_losses", "second_node", "sensor_lag"),  # what the walk often ends with
            ("joule", "speed_losses", "second_node", "housing_friction", "third_node"),  # friction on the housing
            ("joule", "second_node", "third_node"), ("joule", "effort_bias", "sensor_lag"),
            ("joule", "effort_bias", "speed_losses", "winding_tempco"))  # copper's gain beside speed losses


@pytest.mark.parametrize("families", [CASCADES[:2], CASCADES])
def test_actuators_stepped_together_give_what_each_gives_alone(families):
    from dataclasses import replace

    from thermolimb.logs.follow import Run
    from thermolimb.model.saved import ResidualStats, bare

    rng = np.random.default_rng(7)
    saved = {}
    for k in range(10):  # each family; limits some will reach; a slow mass's share of 0 in one
        terms = families[k % len(families)]
        params = {p.name: p.typical for p in model_parameters(terms)}
        params.update({n: v for n, v in dict(
            RC_s=20.0 + 10 * k, betaR_K_per_effort2=0.3 + 0.1 * k, beta_biasR_K_per_effort=0.05 * (k - 4),
            frame_fraction=0.0 if k == 7 else 0.3, frame_tau_s=400.0 + 50 * k, body_fraction=0.2, body_tau_s=3000.0,
            sensor_tau_s=3.0 + k, speed_K_per_rad_s=0.5, speed2_K_per_rad2_s2=0.2).items() if n in params})
        model = ThermalModel(terms, params)
        residual = ResidualStats(100, 100.0, 0.0, 0.2 + 0.05 * k, {"0.9": 0.3}, 0.9, 20.0)
        saved[f"j{k}"] = replace(bare(model, f"j{k}", 45.0 + 5 * k), residual=residual)
    sessions = [Session(ModelFile(saved), {}, [], together=together) for together in (True, False)]
    temperature = {n: 30.0 for n in saved}
    out = []
    for step in range(400):
        pieces = {}
        for n in saved:
            if step % 97 == 5 and n == "j3":
                continue  # an actuator with no new row this time
            temperature[n] += rng.normal(0.02, 0.05)
            arrays = {"time": np.array([0.1 * step + rng.uniform(0, 0.01)]), "effort": rng.uniform(-8, 8, 1),
                      "temperature": np.array([round(temperature[n], 1)]), "velocity": rng.uniform(-3, 3, 1)}
            pieces[n] = [Run(arrays, step == 0)]
        out.append([session.feed({n: [Run(dict(r.arrays), r.new_run) for r in v] for n, v in pieces.items()})
                    for session in sessions])
    for together, alone in out:
        assert len(together) == len(alone)
        by_name = {e.actuator: e for e in alone}
        for e in together:
            a = by_name[e.actuator]
            assert (e.level, e.time_to_limit_s is None) == (a.level, a.time_to_limit_s is None)
            np.testing.assert_allclose([e.winding_C, e.winding_std_K, e.derating, e.time_to_limit_s or 0.0],
                                       [a.winding_C, a.winding_std_K, a.derating, a.time_to_limit_s or 0.0],
                                       rtol=1e-9, atol=1e-9)
    assert {n: m.state.keys() for n, m in sessions[0].monitors.items()} == {
        n: m.state.keys() for n, m in sessions[1].monitors.items()}
    levels = Counter(e.status for together, _ in out for e in together)
    assert levels["OK"] and (levels["WARN"] or levels["ERROR"]), levels  # the limits were approached


def test_time_to_limit_is_first_order():
    assert first_order_reach_s(50.0, 100.0, 0.01, 75.0) == pytest.approx(np.log(2) / 0.01)
    assert first_order_reach_s(50.0, 70.0, 0.01, 75.0) is None
    assert first_order_reach_s(80.0, 70.0, 0.01, 75.0) == 0.0


@pytest.fixture(scope="module")
def model_and_log(tmp_path_factory):
    return model_and_run(tmp_path_factory.mktemp("monitor"), 2400, 600)


def _monitor_while_written(model, live, out, writer_args, head_start_s):
    """``thermolimb monitor --follow live --mcap out`` while another process (``python -c writer_args``) writes
    ``live``: the monitor's completed process."""
    writer = subprocess.Popen([sys.executable, "-c", *writer_args])
    time.sleep(head_start_s)
    try:
        return subprocess.run([str(Path(sys.executable).parent / "thermolimb"), "monitor", str(model), "--follow",
                               str(live), "--mcap", str(out), "--idle-exit", "1.5", "--publish-hz", "1"],
                              capture_output=True, text=True, timeout=120)
    finally:
        writer.wait(timeout=60)


def test_the_monitor_follows_a_file_another_process_appends_to(model_and_log, tmp_path):
    from rosbags.highlevel import AnyReader

    model, run = model_and_log
    live, out = tmp_path / "live.csv", tmp_path / "out.mcap"
    done = _monitor_while_written(model, live, out, [WRITER, str(run), str(live), "30", "0.02"], 0.1)
    assert done.returncode == 0, done.stderr
    rows = len(run.read_text().splitlines()) - 1
    counts, types, levels = Counter(), {}, set()
    with AnyReader([out]) as reader:
        for connection, _, raw in reader.messages():
            counts[connection.topic] += 1
            types[connection.topic] = connection.msgtype
            if connection.topic == "/diagnostics":
                levels |= {s.level for s in reader.deserialize(raw, connection.msgtype).status}
    assert types["/thermolimb/knee/winding_temperature"] == "sensor_msgs/msg/Temperature"
    assert types["/diagnostics"] == "diagnostic_msgs/msg/DiagnosticArray"
    per_actuator = rows // 3
    # one publication per second of log time (1 Hz log): every sample after the first
    assert counts["/thermolimb/knee/winding_temperature"] == per_actuator - 1
    assert counts["/diagnostics"] == per_actuator - 1
    assert levels <= {0, 1, 2}
    assert not list(tmp_path.glob("out.mcap.*"))  # no partial left behind


MCAP_WRITER = """
import sys, time
import numpy as np
from mcap.writer import CompressionType, Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore
from thermolimb.logs import read_log
from thermolimb.logs.bag_writer import THERMAL_DEFINITION, THERMAL_TYPE
log = read_log(sys.argv[1])
store = get_typestore(Stores.ROS2_HUMBLE)
store.register(get_types_from_msg(THERMAL_DEFINITION, THERMAL_TYPE))
names = list(log.actuators)
series = [log.series(n) for n in names]
JS, TH = store.types["sensor_msgs/msg/JointState"], store.types[THERMAL_TYPE]
H, T = store.types["std_msgs/msg/Header"], store.types["builtin_interfaces/msg/Time"]
with open(sys.argv[2], "wb") as f:
    w = Writer(f, chunk_size=2048, compression=CompressionType.NONE)  # a recorder's chunks, small
    w.start("ros2", "test")
    ids = {}
    for topic, msgtype in (("/joint_states", JS.__msgtype__), ("/thermal", THERMAL_TYPE)):
        ids[topic] = w.register_channel(topic, "cdr", w.register_schema(msgtype, "ros2msg",
                                                                        store.generate_msgdef(msgtype)[0].encode()))
    for k in range(series[0].n):
        ns = int(1.7e18 + series[0].time_s[k] * 1e9)
        header = H(stamp=T(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="")
        joint = JS(header=header, name=names, position=np.zeros(len(names)),
                   velocity=np.array([s.signals.velocity[k] for s in series]),
                   effort=np.array([s.signals.effort[k] for s in series]))
        w.add_message(ids["/joint_states"], ns, store.serialize_cdr(joint, JS.__msgtype__), ns)
        thermal = TH(name=names, temperature=np.array([s.temperature_C[k] for s in series]), current=np.zeros(0),
                     housing=np.zeros(0))
        w.add_message(ids["/thermal"], ns, store.serialize_cdr(thermal, THERMAL_TYPE), ns)
        if k % 20 == 0:
            f.flush()
            time.sleep(0.02)
    w.finish()
"""


def test_the_monitor_follows_an_mcap_being_recorded(model_and_log, tmp_path):
    from rosbags.highlevel import AnyReader

    model, run = model_and_log
    live, out = tmp_path / "live.mcap", tmp_path / "out.mcap"
    done = _monitor_while_written(model, live, out, [MCAP_WRITER, str(run), str(live)], 0.2)
    assert done.returncode == 0, done.stderr
    samples = (len(run.read_text().splitlines()) - 1) // 3
    with AnyReader([out]) as reader:
        counts = Counter(connection.topic for connection, _, _ in reader.messages())
    assert counts["/thermolimb/hip/winding_temperature"] == samples - 1 and counts["/diagnostics"] == samples - 1


def test_the_monitor_follows_a_ros2_control_recording_as_a_recorded_bag_is_read(model_and_log, tmp_path):
    """ros2_control's /dynamic_joint_states (a hardware's state interfaces per joint), followed live: each joint gets
    its own temperatures, and a field the message lacks is refused naming those it has, as the bag reader does."""
    from thermolimb.logs import LogError, read_log
    from thermolimb.logs.bag_writer import write_mcap
    from thermolimb.logs.follow_mcap import McapFollower

    model, run = model_and_log
    log = read_log(run)
    path = write_mcap(log, tmp_path / "control.mcap", layout="ros2_control")
    effort = "effort=/joint_states.effort,velocity=/joint_states.velocity"
    pieces = McapFollower(path, f"{effort},temperature=/dynamic_joint_states.temperature").poll(final=True)
    assert set(pieces) == set(log.actuators)
    for name in log.actuators:
        series = log.series(name)
        assert np.array_equal(np.concatenate([p.arrays["temperature"] for p in pieces[name]]), series.temperature_C)
        assert np.array_equal(np.concatenate([p.arrays["effort"] for p in pieces[name]]), series.signals.effort)
    with pytest.raises(LogError, match="has no field 'temp'; its numeric fields are position, velocity, effort, temp"):
        McapFollower(path, f"{effort},temperature=/dynamic_joint_states.temp").poll()
    done = main(["monitor", str(model), "--follow", str(path), "--map", f"{effort},temperature=/dynamic_joint_states."
                 "temperature", "--json-lines", "--idle-exit", "0.2", "--publish-hz", "0.01", "--quiet"])
    assert done == 0


def test_json_lines_and_the_estimate_follows_the_readings(model_and_log, capsys):
    model, run = model_and_log
    session = Session(ModelFile.load(model), {}, [], publish_every_s=0.0)
    follower = CsvFollower(run)
    estimates = session.feed(follower.poll())
    assert {e.actuator for e in estimates} == {"knee", "hip", "ankle"}
    for e in estimates:
        assert abs(e.winding_C - e.measured_C) < 3.0 and 0 < e.winding_std_K < 1.0
        assert 0.0 <= e.derating <= 1.0
    assert main(["monitor", str(model), "--follow", str(run), "--json-lines", "--idle-exit", "0.2",
                 "--publish-hz", "0.01"]) == 0
    lines = capsys.readouterr().out.splitlines()
    records = [json.loads(line) for line in lines]
    assert len(records) >= 2 and set(records[-1]["actuators"]) == {"knee", "hip", "ankle"}


def test_a_run_in_another_air_moves_the_monitor_s_offset_with_it(model_and_log, capsys):
    """The model was identified at 25 degC: followed at 45 degC, with readings and limit 20 K higher, the monitor
    gives what it gives at 25 degC (the offset follows the ambient, Jorgensen et al. Eq. 5), and says so once."""
    model, run = model_and_log
    log = CsvFollower(run).poll()
    knee = {name: pieces for name, pieces in log.items() if name == "knee"}
    same = Session(ModelFile.load(model), {"knee": 45.0}, [], publish_every_s=0.0).feed(knee)[-1]
    assert "offset follows" not in capsys.readouterr().err
    for piece in knee["knee"]:
        piece.arrays["ambient"] = piece.arrays["ambient"] + 20.0
        piece.arrays["temperature"] = piece.arrays["temperature"] + 20.0
    warm = Session(ModelFile.load(model), {"knee": 65.0}, [], publish_every_s=0.0).feed(knee)[-1]
    assert "knee: the ambient here lies beyond the 25.0 to 25.0 degC" in capsys.readouterr().err
    assert warm.winding_C == pytest.approx(same.winding_C + 20.0, abs=1e-6)
    assert 0 < same.time_to_limit_s < 600 and warm.time_to_limit_s == pytest.approx(same.time_to_limit_s, rel=1e-6)


def test_the_live_view_speaks_foxglove_to_a_real_client(model_and_log, tmp_path):
    pytest.importorskip("foxglove")
    websocket = pytest.importorskip("websocket")
    model, run = model_and_log
    live = tmp_path / "live.csv"
    writer = subprocess.Popen([sys.executable, "-c", WRITER, str(run), str(live), "3", "0.05"])
    monitor = subprocess.Popen([str(Path(sys.executable).parent / "thermolimb"), "monitor", str(model), "--follow",
                                str(live), "--foxglove", "0", "--idle-exit", "2"], stderr=subprocess.PIPE, text=True)
    try:
        port = int(re.search(r"ws://127\.0\.0\.1:(\d+)", monitor.stderr.readline()).group(1))
        ws = websocket.create_connection(f"ws://127.0.0.1:{port}", subprotocols=["foxglove.sdk.v1"], timeout=10)
        assert ws.subprotocol == "foxglove.sdk.v1"
        channels, messages = {}, []
        deadline = time.time() + 20
        while time.time() < deadline and len(messages) < 10:
            opcode, data = ws.recv_data()
            if opcode == 1 and json.loads(data)["op"] == "advertise":
                channels.update({c["id"]: c["topic"] for c in json.loads(data)["channels"]})
                ws.send(json.dumps({"op": "subscribe",
                                    "subscriptions": [{"id": cid, "channelId": cid} for cid in channels]}))
            elif opcode == 2 and data[0] == 1:  # message data: opcode, subscription id, time, payload
                messages.append((channels[int.from_bytes(data[1:5], "little")], json.loads(data[13:])))
        ws.close()
    finally:
        writer.kill()
        monitor.wait(timeout=30)
    assert {"/diagnostics", "/thermolimb/knee/winding_temperature", "/thermolimb/hip/measured_temperature"} <= \
        set(channels.values())
    assert len(messages) >= 10
    topic, payload = next((t, p) for t, p in messages if t.endswith("winding_temperature"))
    assert 0.0 < payload["temperature"] < 200.0 and payload["variance"] >= 0.0


def test_the_shipped_layout_is_the_generated_one():
    from importlib.resources import files

    shipped = files("thermolimb.data").joinpath("foxglove_layout.json").read_text()
    assert shipped == layout_text(SHIPPED_ACTUATORS)
    assert "/thermolimb/knee/winding_temperature.temperature" in shipped and "/diagnostics" in shipped


@pytest.mark.parametrize("argv, message", [
    (["--follow", "{run}"], "monitor needs somewhere to publish"),
    (["--follow", "{run}", "--mcap", "{run}"], "an output never replaces an input"),
])
def test_monitor_refuses_in_one_sentence(model_and_log, capsys, argv, message):
    model, run = model_and_log
    assert main(["monitor", str(model)] + [a.format(run=run) for a in argv]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_an_environment_streams_its_world_on_the_same_channels():
    pytest.importorskip("foxglove")
    websocket = pytest.importorskip("websocket")
    import gymnasium as gym

    from hexapod_pb import ENV_ID
    from thermolimb.monitor.live import live_view

    with pytest.raises(ValueError, match="live must be None or a port number"):
        gym.make(ENV_ID, live=-1)
    env = gym.make(ENV_ID, live=0, max_time_s=5.0)
    try:
        env.reset(seed=0)
        env.step(env.action_space.sample())
        ws = websocket.create_connection(f"ws://127.0.0.1:{live_view(0).port}", subprotocols=["foxglove.sdk.v1"],
                                         timeout=10)
        channels = {}
        while "/diagnostics" not in channels.values() or len(channels) < 37:
            opcode, data = ws.recv_data()
            if opcode == 1 and json.loads(data)["op"] == "advertise":
                channels.update({c["id"]: c["topic"] for c in json.loads(data)["channels"]})
        ws.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": c, "channelId": c} for c in channels]}))
        env.step(env.action_space.sample())
        opcode, data = ws.recv_data()
        ws.close()
    finally:
        env.close()
    # 18 actuators, each an estimated and a measured temperature, and the diagnostics
    assert len(channels) == 37 and "/thermolimb/left_front_base/winding_temperature" in channels.values()
    assert opcode == 2 and data[0] == 1 and {"temperature", "status"} & set(json.loads(data[13:]))

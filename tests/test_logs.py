import numpy as np
import pandas as pd
import pytest

from thermolimb.logs import LogError, from_frame, parse_mapping, read_log


def canonical(n=50):
    t = np.arange(n) * 0.5
    return pd.DataFrame({"time": t, "actuator": "knee", "effort": np.sin(t), "temperature": 25 + 0.01 * t})


def write(tmp_path, frame, name="log.csv"):
    path = tmp_path / name
    frame.to_csv(path, index=False)
    return path


def test_roundtrip_csv_and_parquet(tmp_path, plant_log):
    for name in ("a.csv", "a.parquet"):
        path = plant_log.write(tmp_path / name)
        again = read_log(path)
        assert again.actuators == plant_log.actuators
        pd.testing.assert_frame_equal(again.frame, plant_log.frame, check_dtype=False)


def test_missing_column(tmp_path):
    path = write(tmp_path, canonical().drop(columns="effort"))
    with pytest.raises(LogError, match=r"log.csv: missing column\(s\) effort .*--map"):
        read_log(path)


def test_a_canonical_file_of_one_actuator_needs_no_actuator_column(tmp_path):
    """``time [s], effort, temperature [K]`` and nothing naming the actuator: one actuator, named after the file, or
    by the one actuator asked for (as a wide file read with --map is); it was refused for its missing actuator column
    though every channel was there."""
    frame = canonical().drop(columns="actuator").rename(columns={"time": "time [s]", "temperature": "temperature [K]"})
    frame["temperature [K]"] += 273.15
    path = write(tmp_path, frame, "wrist.csv")
    log = read_log(path)
    assert log.actuators == ("wrist",) and log.series("wrist").temperature_C[0] == pytest.approx(25.0)
    assert read_log(path, actuators=["knee"]).actuators == ("knee",)
    with pytest.raises(LogError, match="missing column"):  # a channel missing is still refused
        read_log(write(tmp_path, canonical().drop(columns=["actuator", "effort"]), "other.csv"))


def test_inspect_says_when_a_file_reads_without_a_map(tmp_path, capsys):
    """Canonical names (bare, or with the unit in the header): inspect says no --map is needed; a file whose
    columns need the map (``tau`` for the effort) is not said to."""
    from thermolimb.cli.main import main

    frame = canonical().drop(columns="actuator").rename(columns={"temperature": "temperature [degC]"})
    said = "read the file as it is, without --map"
    assert main(["inspect", str(write(tmp_path, frame, "plain.csv"))]) == 0
    assert said in capsys.readouterr().out
    assert main(["inspect", str(write(tmp_path, frame.rename(columns={"effort": "tau"}), "tau.csv"))]) == 0
    assert said not in capsys.readouterr().out


def test_nan(tmp_path):
    frame = canonical()
    frame.loc[7, "temperature"] = np.nan
    with pytest.raises(LogError, match=r"column 'temperature' has 1 missing .* first at row 7"):
        read_log(write(tmp_path, frame))


def test_not_numeric(tmp_path):
    frame = canonical().astype({"effort": object})
    frame.loc[3, "effort"] = "high"
    with pytest.raises(LogError, match=r"column 'effort' is not numeric at row 3"):
        read_log(write(tmp_path, frame))


def test_time_not_increasing(tmp_path):
    frame = canonical()
    frame.loc[10, "time"] = frame.loc[9, "time"]
    with pytest.raises(LogError, match=r"time does not increase for actuator 'knee' at row 10") as error:
        read_log(write(tmp_path, frame))
    assert "clocks restart" not in str(error.value)  # a repeated stamp is no restart
    frame = canonical()
    frame.loc[20:, "time"] -= frame.loc[20, "time"]  # two recordings joined: the second's clock starts at zero
    with pytest.raises(LogError, match=r"at row 20 \(t = .* s then 0 s\); expected strictly increasing time in "
                                       r"seconds; if it joins recordings whose clocks restart, give each as a file of "
                                       r"its own \(a run each\)"):
        read_log(write(tmp_path, frame))
    # a long log of several actuators read by a map that names no actuator column: its rows are one actuator's
    long = canonical().rename(columns={"actuator": "motor_id", "temperature": "winding_temp"})
    long = pd.concat([long.assign(motor_id=1), long.assign(motor_id=2)]).sort_values("time", kind="stable")
    with pytest.raises(LogError, match=r"\(t = 0 s then 0 s\); expected strictly increasing time in seconds; if the "
                                       r"file holds rows of several actuators, map the column naming them "
                                       r"\(--map actuator=COLUMN\)$"):
        read_log(write(tmp_path, long), mapping=parse_mapping("time=time,effort=effort,temperature=winding_temp"))
    from thermolimb.logs.mapping import suggest_table_mapping

    mapping, _ = suggest_table_mapping(list(long.columns), dict.fromkeys(long.columns, len(long)))
    assert mapping["actuator"] == "motor_id"
    assert read_log(write(tmp_path, long), mapping=mapping).actuators == ("1", "2")


def test_too_short(tmp_path):
    with pytest.raises(LogError, match=r"'knee' has 5 samples; at least 20"):
        read_log(write(tmp_path, canonical(5)))


def test_unknown_actuator(tmp_path):
    log = read_log(write(tmp_path, canonical()))
    with pytest.raises(LogError, match=r"no actuator 'hip'; the log has knee"):
        log.series("hip")


def test_unknown_format_and_missing_file(tmp_path):
    with pytest.raises(LogError, match=r"unknown log format '.xls'"):
        read_log(tmp_path / "log.xls")
    with pytest.raises(LogError, match="no such file"):
        read_log(tmp_path / "absent.csv")


def test_wide_file_by_column_map(tmp_path):
    n = 40
    wide = pd.DataFrame({"t": np.arange(n) * 2.5, "torque": np.linspace(0, 60, n), "stator_winding": 20 + np.arange(n) * 0.1,
                         "motor_speed": np.full(n, 600.0), "coolant": 19.5, "current": 3.0})
    path = write(tmp_path, wide, "profile.csv")
    mapping = parse_mapping("time=t,effort=torque,velocity=motor_speed,temperature=stator_winding,"
                            "ambient=coolant,current=current")
    log = read_log(path, mapping=mapping, velocity_unit="rpm")
    assert log.actuators == ("profile",)
    series = log.series("profile")
    np.testing.assert_allclose(series.signals.velocity, 600.0 * 2 * np.pi / 60)
    np.testing.assert_allclose(series.signals.ambient_C, 19.5)
    # revolutions a second (ODrive's and moteus's velocity), stated after the column or in the header
    for unit in ("rev/s", "turn/s"):
        turns = read_log(path, mapping={**mapping, "velocity": f"motor_speed:{unit}"}).series("profile")
        np.testing.assert_allclose(turns.signals.velocity, 600.0 * 2 * np.pi)
    write(tmp_path, wide.rename(columns={"motor_speed": "vel_estimate [rev/s]"}), "odrive.csv")
    turns = read_log(tmp_path / "odrive.csv", mapping={**mapping, "velocity": "vel_estimate [rev/s]"})
    np.testing.assert_allclose(turns.series("odrive").signals.velocity, 600.0 * 2 * np.pi)
    with pytest.raises(LogError, match=r"--map effort=torq names column 'torq', which the file does not have"):
        read_log(path, mapping={**mapping, "effort": "torq"})
    with pytest.raises(LogError, match=r"--map does not name the column\(s\) for time, temperature; add time=COLUMN"):
        read_log(path, mapping={"effort": "torque"})
    with pytest.raises(LogError, match=r"--map names 'torque', which is not a log column"):
        parse_mapping("torque=torque")


def test_a_joint_pattern_s_shared_column_must_be_a_column(tmp_path):
    n = 40
    wide = pd.DataFrame({"t": np.arange(n) * 2.5, "cur1": 1.0, "cur2": 2.0, "temp1": 30.0 + np.arange(n) * 0.1,
                         "temp2": 31.0 + np.arange(n) * 0.1})
    path = write(tmp_path, wide, "arm.csv")
    with pytest.raises(LogError, match=r"--map temperature=temp\* names column 'temp\*', which the file does not have "
                                       r"\(a column per joint needs \{j\} where its number stands\)"):
        read_log(path, mapping={"time": "t", "effort": "cur{j}", "temperature": "temp*"})
    with pytest.raises(LogError, match=r"--map time=stamp names column 'stamp'"):
        read_log(path, mapping={"time": "stamp", "effort": "cur{j}", "temperature": "temp{j}"})
    assert read_log(path, mapping={"time": "t", "effort": "cur{j}", "temperature": "temp{j}"}).actuators == ("J1", "J2")


def test_split_keeps_the_split_sample_in_both_parts():
    log = from_frame(canonical(100))
    train, valid = log.series("knee").split(0.7)
    assert train.time_s[-1] == valid.time_s[0]
    assert train.time_s[-1] == pytest.approx(0.7 * 49.5, abs=0.5)


def test_neighbours_are_the_adjacent_actuators_in_log_order(plant_log):
    frame = plant_log.frame.copy()
    parts = [frame.assign(actuator=name, temperature=frame["temperature"] + i)
             for i, name in enumerate(("hip", "knee", "ankle"))]
    log = from_frame(pd.concat(parts))
    assert log.series("hip").signals.neighbor_names == ("knee",)
    assert log.series("knee").signals.neighbor_names == ("hip", "ankle")
    s = log.series("ankle").signals
    np.testing.assert_allclose(s.neighbor_temperature_C[:, 0], log.series("knee").temperature_C)


def test_inspect_suggests_a_map_for_wide_files_as_for_bags(tmp_path):
    from thermolimb.logs.mapping import suggest_table_mapping

    ur3 = ("Num;Timestamp;Current_J0;Temperature_T0;Current_J1;Temperature_J1;Current_J2;Temperature_J2;Speed_J0;"
           "Speed_J1;Speed_J2;Tool_current;Unnamed: 24").split(";")
    values = {c: 0 if c.startswith("Unnamed") else 10 for c in ur3}
    mapping, notes = suggest_table_mapping(ur3, values)
    assert mapping == {"time": "Timestamp", "temperature": "Temperature_*{j}", "velocity": "Speed_J{j}",
                       "effort": "Current_J{j}"}
    assert notes == ["no torque or effort column: the motor current stands for effort"]
    bench = ["time", "u_q", "coolant", "stator_winding", "motor_speed", "i_d", "ambient", "torque", "current"]
    mapping, _ = suggest_table_mapping(bench, dict.fromkeys(bench, 5))
    assert mapping["effort"] == "torque" and mapping["temperature"] == "stator_winding" and mapping["time"] == "time"
    rostopic = ["%time", "field.header.stamp", "field.effort0", "field.temperature"]  # `rostopic echo -p`, one joint
    mapping, notes = suggest_table_mapping(rostopic, dict.fromkeys(rostopic, 5))
    assert mapping == {"time": "%time", "temperature": "field.temperature", "effort": "field.effort0"} and not notes
    several = ["Temperature Time [s]", "States Time [s]", "Commands Time [s]", "Temp [C]", "Effort [mA]"]
    mapping, notes = suggest_table_mapping(several, dict.fromkeys(several, 5))  # a time column per topic
    assert mapping == {"temperature": "Temp [C]@Temperature Time [s]", "effort": "Effort [mA]@States Time [s]"}
    assert notes == ["each channel has a time column of its own: temperature on Temperature Time [s] (5 values); "
                     "effort on States Time [s] (5 values)"]
    several = ["Logger A Time [s]", "Logger B Time [s]", "Temp [C]", "Effort [mA]"]
    mapping, notes = suggest_table_mapping(several, dict.fromkeys(several, 5))  # no name says which
    assert "time" not in mapping and any("several columns" in n for n in notes)
    short = ["stamp", "tau_Nm", "motor_temp", "battery_level", "travel_mm", "joint_vel"]  # short names, whole words
    mapping, notes = suggest_table_mapping(short, dict.fromkeys(short, 5))
    assert mapping == {"time": "stamp", "temperature": "motor_temp", "effort": "tau_Nm:Nm", "velocity": "joint_vel"}
    assert notes == ["effort=tau_Nm: its name ends in a unit, so the suggestion states it (Nm); change it if the name "
                     "means otherwise"]
    # per-joint temperatures of the motor and of what is not the motor (moteus's servo1.temperature is its board's;
    # an ODrive's FETs), whichever comes first in the file
    for other in ("servo{}.temperature", "axis{}.motor.fet_thermistor.temperature"):
        drivers = ["time"] + [f.format(i) for i in (1, 2)
                              for f in (other, "servo{}.motor_temperature", "servo{}.torque")]
        mapping, notes = suggest_table_mapping(drivers, dict.fromkeys(drivers, 5))
        assert mapping["temperature"] == "servo{j}.motor_temperature", other
        assert notes[0].startswith("temperature: servo{j}.motor_temperature names the motor, " + other.format("{j}"))
    # a driver's log: the motor's thermistor beside its FETs', units at the ends of the names
    odrive = ["timestamp_ns", "axis0.motor.motor_thermistor.temperature", "axis0.motor.fet_thermistor.temperature",
              "Iq_measured_A", "vel_estimate_rpm", "bus_voltage"]
    mapping, notes = suggest_table_mapping(odrive, dict.fromkeys(odrive, 5))
    assert mapping == {"time": "timestamp_ns:ns", "temperature": "axis0.motor.motor_thermistor.temperature",
                       "effort": "Iq_measured_A:A", "velocity": "vel_estimate_rpm:rpm"}
    assert "axis0.motor.fet_thermistor.temperature its electronics" in notes[0]
    # a driver's logger: a joint's number joined to each word (motor1_temp beside fet1_temp), time in ms
    logger = ["timestamp_ms", "motor1_current_mA", "motor1_temp_degC", "fet1_temp_degC", "motor1_velocity_rpm"]
    mapping, notes = suggest_table_mapping(logger, dict.fromkeys(logger, 5))
    assert mapping == {"time": "timestamp_ms:ms", "temperature": "motor1_temp_degC", "effort": "motor1_current_mA:mA",
                       "velocity": "motor1_velocity_rpm:rpm"}
    for columns, scale in ((logger, 1e3), (odrive, 1e9)):  # the stated unit read: 100 s, not 100,000 or 1e11
        mapping, _ = suggest_table_mapping(columns, dict.fromkeys(columns, 5))
        path = tmp_path / f"{columns[0]}.csv"
        pd.DataFrame({c: (1.0 + np.arange(21.0) * 5.0) * scale if c == columns[0] else np.full(21, 30.0 + len(c))
                      for c in columns}).to_csv(path, index=False)
        log = read_log(path, mapping=mapping)
        run = log.series(log.actuators[0])
        assert run.duration_s == pytest.approx(100.0), columns[0]
    # two temperatures that do not say which is the motor's are left to the user
    plain = ["t", "temp_1st", "temp_2nd", "torque"]
    mapping, notes = suggest_table_mapping(plain, dict.fromkeys(plain, 5))
    assert "temperature" not in mapping and any("several columns could be it" in n for n in notes)
    # per-joint columns whose names share a first word (motor_temp_0 beside motor_current_0), and a PlotJuggler
    # export (__time, /joint_states/effort.0): each channel its own pattern; a column named t is the time
    grouped = ["t", "motor_temp_0", "motor_temp_1", "motor_current_0", "motor_current_1", "joint_pos_0", "joint_pos_1"]
    mapping, _ = suggest_table_mapping(grouped, dict.fromkeys(grouped, 5))
    assert mapping == {"time": "t", "temperature": "motor_temp_{j}", "effort": "motor_current_{j}"}
    plotjuggler = ["__time", "/joint_states/effort.0", "/joint_states/effort.1", "/joint_states/velocity.0",
                   "/joint_states/velocity.1", "/temps/data.0", "/temps/data.1"]
    mapping, notes = suggest_table_mapping(plotjuggler, dict.fromkeys(plotjuggler, 5))
    assert mapping == {"time": "__time", "temperature": "/temps/data.{j}", "effort": "/joint_states/effort.{j}",
                       "velocity": "/joint_states/velocity.{j}"} and not notes
    path = tmp_path / "plotjuggler.csv"
    frame = pd.DataFrame({c: np.arange(20.0) if c == "__time" else np.full(20, 30.0) for c in plotjuggler})
    frame.to_csv(path, index=False)
    assert read_log(path, mapping=mapping).actuators == ("J0", "J1")
    named = ["__time", "/joint_states/hip/effort", "/joint_states/knee/effort", "/joint_states/hip/velocity",
             "/joint_states/knee/velocity", "/motor_temperature/hip", "/motor_temperature/knee"]
    mapping, notes = suggest_table_mapping(named, dict.fromkeys(named, 5))  # joints named, not numbered: {j} a name
    assert mapping == {"time": "__time", "temperature": "/motor_temperature/{j}", "effort": "/joint_states/{j}/effort",
                       "velocity": "/joint_states/{j}/velocity"}
    assert notes[0].startswith("the columns name their joints (hip, knee) rather than number them: {j} in this map")
    # a PlotJuggler export of a quadruped: names with underscores, a gripper in the JointState without a temperature,
    # positions beside: every heated joint is an actuator named so, in the file's order, its position an extra channel
    joints = ("FR_hip", "FR_calf", "FL_calf")
    quad = ["__time"] + [f"/joint_states/{j}/{f}" for j in (*joints, "gripper") for f in ("position", "effort")] + [
        f"/motor_temperatures/{j}/temperature" for j in joints]
    mapping, notes = suggest_table_mapping(quad, dict.fromkeys(quad, 5))
    assert mapping == {"time": "__time", "temperature": "/motor_temperatures/{j}/temperature",
                       "effort": "/joint_states/{j}/effort"}
    path = tmp_path / "quad.csv"
    pd.DataFrame({c: np.arange(20.0) if c == "__time" else 30.0 + (np.arange(20) % (3 + len(c) % 5)) for c in quad}
                 ).to_csv(path, index=False)
    log = read_log(path, mapping=mapping)
    assert log.actuators == joints
    calf = log.series("FR_calf")
    assert np.array_equal(calf.signals.extra["/joint_states/position"],
                          pd.read_csv(path)["/joint_states/FR_calf/position"])
    assert np.array_equal(calf.signals.effort, pd.read_csv(path)["/joint_states/FR_calf/effort"])
    pd.read_csv(path).drop(columns="/joint_states/FL_calf/effort").to_csv(path, index=False)  # a joint left out, said
    _, notes = suggest_table_mapping([c for c in quad if c != "/joint_states/FL_calf/effort"], dict.fromkeys(quad, 5))
    assert notes[0].endswith("{j} in this map stands for a joint's name; FL_calf has no effort column, so it is not "
                             "read")
    log = read_log(path, mapping=mapping)
    assert log.actuators == joints[:2] and "joint(s) FL_calf not read: the map finds their temperature but not " \
        "effort" in str(log.notes)
    with pytest.raises(LogError, match="--map temperature=/motor_temperatures/{j}/temp matches no column"):
        read_log(path, mapping={**mapping, "temperature": "/motor_temperatures/{j}/temp"})  # named for what is wrong
    # rostopic echo -p of a JointState, its temperatures merged in: field.name{j} names each joint's actuator
    echo = ["%time", "field.header.seq"] + [f"field.{f}{i}" for f in ("name", "effort", "temperature") for i in (0, 1)]
    mapping, notes = suggest_table_mapping(echo, dict.fromkeys(echo, 5))
    assert mapping == {"time": "%time", "temperature": "field.temperature{j}", "effort": "field.effort{j}",
                       "actuator": "field.name{j}"}
    frame = pd.DataFrame({c: np.arange(20.0) if c in echo[:2] else np.full(20, 30.0) for c in echo}).assign(
        **{"field.name0": "left_knee", "field.name1": "right_knee"})
    frame.to_csv(path := tmp_path / "echo.csv", index=False)
    log = read_log(path, mapping=mapping)
    assert log.actuators == ("left_knee", "right_knee") and not log.extras
    frame.loc[5, "field.name1"] = "right_hip"
    frame.to_csv(path, index=False)
    with pytest.raises(LogError, match="column 'field.name1', which holds 2 names"):
        read_log(path, mapping=mapping)
    path = tmp_path / "driver.csv"
    pd.DataFrame({"time": np.arange(20.0), "tau_Nm": np.ones(20), "motor_temp": np.full(20, 30.0)}).to_csv(path)
    log = read_log(path, mapping=parse_mapping("time=time,effort=tau_Nm:Nm,temperature=motor_temp"))
    assert log.series(log.actuators[0]).units["effort"] == "Nm"
    inside = ["stamp", "joint1_effort", "joint1_temp", "joint2_effort", "joint2_temp", "joint1_vel", "joint2_vel"]
    mapping, notes = suggest_table_mapping(inside, dict.fromkeys(inside, 5))  # the joint's number inside the name
    assert mapping == {"time": "stamp", "temperature": "joint{j}_temp", "effort": "joint{j}_effort",
                       "velocity": "joint{j}_vel"} and not notes
    path = tmp_path / "wide.csv"
    pd.DataFrame({c: np.arange(20.0) if c == "stamp" else np.full(20, 30.0) for c in inside}).to_csv(path, index=False)
    log = read_log(path, mapping=mapping)  # the suggestion reads: one actuator a joint
    assert log.actuators == ("J1", "J2")


@pytest.mark.parametrize("suffix", [".csv", ".parquet"])
def test_one_actuator_read_in_pieces_is_the_whole_files_series(plant_log, tmp_path, monkeypatch, suffix):
    """``read_log(actuators=...)`` keeps an actuator's rows and its neighbours' temperatures piece by piece (in
    Arrow for Parquet, a row group at a time): the series, its neighbours and the log's order are those of
    reading the whole file, with pieces (CSV chunks, Parquet row groups) of 97 rows so that actuators and
    neighbours straddle them."""
    from thermolimb.logs import read_log, table

    frame = plant_log.frame.copy()
    parts = [frame.assign(actuator=name, temperature=frame["temperature"] + i, effort=frame["effort"] * (i + 1))
             for i, name in enumerate(("hip", "knee", "ankle"))]
    path = tmp_path / f"three{suffix}"
    whole = pd.concat(parts, ignore_index=True).sample(frac=1.0, random_state=0).sort_values("time", kind="stable")
    whole.to_csv(path, index=False) if suffix == ".csv" else whole.to_parquet(path, index=False, row_group_size=97)
    monkeypatch.setattr(table, "CHUNK_ROWS", 97)
    everything = read_log(path)
    for name in ("hip", "knee", "ankle"):
        one = read_log(path, actuators=[name])
        assert one.actuators == (name,)
        a, b = one.series(name), everything.series(name)
        np.testing.assert_array_equal(a.temperature_C, b.temperature_C)
        np.testing.assert_array_equal(a.signals.effort, b.signals.effort)
        assert a.signals.neighbor_names == b.signals.neighbor_names
        np.testing.assert_array_equal(a.signals.neighbor_temperature_C, b.signals.neighbor_temperature_C)
        alone = read_log(path, actuators=[name], neighbours=False).series(name)
        np.testing.assert_array_equal(alone.temperature_C, b.temperature_C)
        assert alone.signals.neighbor_temperature_C is None and alone.signals.neighbor_names == ()


def test_fit_reads_the_neighbours_only_for_a_model_with_their_coupling(tmp_path):
    """``fit --actuator`` on a canonical table leaves the neighbours unread for the default model (it has no use
    for them) and reads them for a model with ``neighbor_coupling``, which then fits."""
    from argparse import Namespace

    from thermolimb.cli.reading import reads_neighbours

    assert not reads_neighbours(Namespace(model="joule,effort_bias", discovers=False))
    assert reads_neighbours(Namespace(model="joule,neighbor_coupling", discovers=False))
    assert not reads_neighbours(Namespace(model=None, discovers=False))  # compare's default: the default model
    assert reads_neighbours(Namespace(model=["joule", "joule,neighbor_coupling"], discovers=False))
    assert reads_neighbours(Namespace(model="joule,effort_bias"))  # diagnose: it may propose the coupling
    assert reads_neighbours(Namespace())  # a command without models reads what it always did


def test_inspect_pairs_each_channel_with_its_own_time_and_reads_topics_merged_on_one(tmp_path, capsys):
    """A log of topics on time bases of their own is read as its lab wrote it, from what ``inspect`` suggests:
    the WidowX-200's exports (a time column per topic, summary columns of one value beside them) pair each
    channel with its time column, or, where those columns agree on every row, read each row as one sample; a table
    whose rows are messages of different topics under one time column (the temperature and the effort never on one
    row) is read on each channel's own samples, and the plain map is refused in a sentence that gives that map. A
    mapped column with no value at all is refused by name.
    """
    from thermolimb.cli.main import main
    from thermolimb.data import REAL_DIR

    for path in sorted((REAL_DIR / "interbotix-wx200").glob("*.csv")):
        assert main(["inspect", str(path)]) == 0
        out = capsys.readouterr().out
        line = next(x for x in out.splitlines() if x.startswith("suggested: --map "))
        mapping = line.removeprefix("suggested: --map ").strip('"')
        if path.name == "waist_diagnostics.csv":  # 21 temperatures beside 1178 joint states: each on its own time
            assert mapping == ("temperature=Temp [C]@Temperature Time [s],effort=Effort [mA]@States Time [s],"
                               "velocity=Velocity [rad/s]@States Time [s]")
            assert "each channel has a time column of its own" in out
        else:  # the bearing runs: every row a sample of every channel, the time columns within 5.4 ms of each other
            assert mapping == ("temperature=Temp [C],effort=Effort [mA],velocity=Velocity [rad/s],"
                               "time=Temperature Time [s]"), path.name
            assert "the channels' time columns agree on every row (to " in out
        log = read_log(path, mapping=parse_mapping(mapping))
        run = log.series(log.actuators[0])
        assert run.n >= 20 and np.ptp(run.temperature_C) >= 1.0, path.name
    t = np.arange(400.0)
    effort = 5.0 + 4.0 * np.sin(t / 40.0)
    temperature = 30.0 + np.cumsum(effort**2) * 1e-3
    merged = pd.DataFrame({"t_s": t, "tau_Nm": np.where(t % 2 == 1, effort, np.nan),
                           "motor_temp_C": np.where(t % 2 == 0, np.round(temperature, 2), np.nan), "i_A": np.nan})
    path = tmp_path / "merged.csv"
    merged.to_csv(path, index=False)
    assert main(["inspect", str(path)]) == 0
    out = capsys.readouterr().out
    assert 'suggested: --map "temperature=motor_temp_C@t_s,effort=tau_Nm@t_s:Nm,time=t_s"' in out
    assert "the temperature and the effort are logged on different rows (0 of the temperature's rows" in out
    for flags in ([], ["--drop-incomplete"]):
        assert main(["fit", str(path), "--map", "time=t_s,effort=tau_Nm,temperature=motor_temp_C", *flags]) == 2
        err = capsys.readouterr().err
        assert "the temperature and the effort are logged on different rows (0 of the temperature's 200 rows" in err
        assert err.rstrip().endswith('--map "time=t_s,effort=tau_Nm@t_s,temperature=motor_temp_C@t_s"')
    # each channel on the rows that hold it, the other topic's rows no missing readings: no --drop-incomplete
    log = read_log(path, mapping=parse_mapping("time=t_s,effort=tau_Nm@t_s:Nm,temperature=motor_temp_C@t_s"))
    assert "effort read on the 200 rows of t_s that hold it (the other 200 hold other channels' messages)" in str(
        log.notes)
    run = log.series(log.actuators[0])
    # t = 0 precedes the first effort; a reading's two-second interval holds for a second each the effort logged a
    # second before it and the one a second after (their root mean square: the heat of the interval)
    assert run.n == 199
    assert np.allclose(run.signals.effort[:-1], np.sqrt((effort[1:396:2] ** 2 + effort[3:398:2] ** 2) / 2.0))
    with pytest.raises(LogError, match="column 'current' \\(the file's 'i_A'\\) holds no value in any of its 400 "
                                       "rows; expected numbers in A, or leave current out of --map"):
        read_log(path, mapping=parse_mapping("time=t_s,effort=tau_Nm,temperature=motor_temp_C,current=i_A"),
                 drop_incomplete=True)
    # a PlotJuggler export of two topics at their own rates, joints named in the columns: each joint read on its own
    # samples as the one-joint table above is
    plot = pd.DataFrame({"__time": t, "/joint_states/hip/effort": merged["tau_Nm"],
                         "/joint_states/knee/effort": 2.0 * merged["tau_Nm"],
                         "/temps/hip/temperature": merged["motor_temp_C"],
                         "/temps/knee/temperature": merged["motor_temp_C"] + 1.0})
    plot.to_csv(path := tmp_path / "plotjuggler.csv", index=False)
    assert main(["inspect", str(path)]) == 0
    map_ = "time=__time,temperature=/temps/{j}/temperature@__time,effort=/joint_states/{j}/effort@__time"
    assert f'suggested: --map "{map_}"' in capsys.readouterr().out
    log = read_log(path, mapping=parse_mapping(map_))
    assert log.actuators == ("hip", "knee")
    assert np.array_equal(log.series("hip").signals.effort, run.signals.effort)
    assert np.allclose(log.series("knee").signals.effort, 2.0 * run.signals.effort)
    assert np.array_equal(log.series("knee").temperature_C, run.temperature_C + 1.0)

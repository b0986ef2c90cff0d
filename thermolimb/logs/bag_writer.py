"""Write a thermal log as a ROS 2 MCAP file that opens in Foxglove and reads back with :mod:`.bags`.

Topics (receive time = the log's time stamps, from the Unix epoch 0 plus ``START_NS``):

* ``/joint_states`` — ``sensor_msgs/msg/JointState``: ``name``, ``effort``, ``velocity`` (zeros when absent)
* ``/thermal`` — ``thermolimb_msgs/msg/ActuatorThermal``, a custom message whose definition is stored in
  the file: ``name``, ``temperature`` (degC) and, when the log has them, ``current`` (A), ``housing`` (degC)
* ``/ambient`` — ``sensor_msgs/msg/Temperature`` (degC), when the log has an ambient channel

With ``layout="per_joint"`` the temperatures go instead, as many robots publish them, to one
``sensor_msgs/msg/Temperature`` topic per joint, ``/<joint>/temperature`` (read back with
``temperature=/{j}/temperature.temperature``, which ``inspect`` suggests), every ``temperature_every``-th
sample. With ``layout="ros2_control"`` they go, as ros2_control's joint state broadcaster publishes a
hardware's state interfaces, to ``/dynamic_joint_states`` (``control_msgs/msg/DynamicJointState``: per joint
its interfaces' names and values, ``position``, ``velocity``, ``effort``, ``temperature`` and, when the log
has it, ``current``), beside ``/joint_states``.

Every actuator must share one time base (as the plant's logs do).
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np

from ..util.atomic import atomic_path
from ..util.errors import LogError

THERMAL_TYPE = "thermolimb_msgs/msg/ActuatorThermal"
THERMAL_DEFINITION = """string[] name
float64[] temperature
float64[] current
float64[] housing
"""
INTERFACE_TYPE, DYNAMIC_TYPE = "control_msgs/msg/InterfaceValue", "control_msgs/msg/DynamicJointState"
CONTROL_DEFINITIONS = {INTERFACE_TYPE: "string[] interface_names\nfloat64[] values\n",
                       DYNAMIC_TYPE: "std_msgs/Header header\nstring[] joint_names\n"
                                     "control_msgs/InterfaceValue[] interface_values\n"}
LAYOUTS = ("thermal", "per_joint", "ros2_control")
START_NS = 1_700_000_000 * 10**9
MAPPING = ("effort=/joint_states.effort,velocity=/joint_states.velocity,temperature=/thermal.temperature")


def _matrix(log, column: str) -> np.ndarray | None:
    if column not in log.frame.columns:
        return None
    return np.column_stack([g[column].to_numpy(float) for _, g in log.frame.groupby("actuator", sort=False)])


def write_mcap(log, path: str | Path, layout: str = "thermal", temperature_every: int = 1) -> Path:
    """Write ``log`` to ``path`` (``.mcap``), whole or not at all (``layout``: one of :data:`LAYOUTS`, module
    docstring)."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    if layout not in LAYOUTS:
        raise ValueError(f"layout must be one of {', '.join(LAYOUTS)}, got {layout!r}")
    path = Path(path)
    names = list(log.actuators)
    groups = [g["time"].to_numpy(float) for _, g in log.frame.groupby("actuator", sort=False)]
    if any(t.shape != groups[0].shape or not np.array_equal(t, groups[0]) for t in groups):
        raise LogError(f"{path}: the actuators of {log.source} have different time stamps; an MCAP log holds "
                       f"every actuator in one message per sample")
    time_s = groups[0]
    store = get_typestore(Stores.ROS2_HUMBLE)
    store.register(get_types_from_msg(THERMAL_DEFINITION, THERMAL_TYPE))
    for msgtype, definition in CONTROL_DEFINITIONS.items():
        store.register(get_types_from_msg(definition, msgtype))
    JointState = store.types["sensor_msgs/msg/JointState"]
    Header = store.types["std_msgs/msg/Header"]
    Time = store.types["builtin_interfaces/msg/Time"]
    Thermal = store.types[THERMAL_TYPE]
    TemperatureMsg = store.types["sensor_msgs/msg/Temperature"]
    Interface, Dynamic = store.types[INTERFACE_TYPE], store.types[DYNAMIC_TYPE]
    effort, temperature = _matrix(log, "effort"), _matrix(log, "temperature")
    velocity, current, housing = _matrix(log, "velocity"), _matrix(log, "current"), _matrix(log, "housing")
    ambient = _matrix(log, "ambient")
    zeros = np.zeros(len(names))
    empty = np.zeros(0)
    still = np.zeros_like(effort)
    interfaces = {"position": still, "velocity": still if velocity is None else velocity, "effort": effort,
                  "temperature": temperature} | ({} if current is None else {"current": current})
    # sample x joint x interface, for the ros2_control layout alone
    stacked = np.stack(list(interfaces.values()), axis=-1) if layout == "ros2_control" else None
    with atomic_path(path) as tmp:
        folder = Path(tempfile.mkdtemp(prefix=".bag-", dir=path.parent)) / "bag"
        try:
            with Writer(folder, version=8, storage_plugin=StoragePlugin.MCAP) as writer:
                states = writer.add_connection("/joint_states", JointState.__msgtype__, typestore=store)
                thermal = None if layout != "thermal" else writer.add_connection(
                    "/thermal", THERMAL_TYPE, typestore=store, msgdef=THERMAL_DEFINITION)
                dynamic = None if layout != "ros2_control" else writer.add_connection(
                    "/dynamic_joint_states", DYNAMIC_TYPE, typestore=store)
                joints = (
                    [
                        writer.add_connection(
                            f"/{n}/temperature", TemperatureMsg.__msgtype__, typestore=store
                        )
                        for n in names
                    ]
                    if layout == "per_joint"
                    else []
                )
                air = writer.add_connection("/ambient", TemperatureMsg.__msgtype__, typestore=store) \
                    if ambient is not None else None
                for k, t in enumerate(time_s):
                    ns = START_NS + int(round(t * 1e9))
                    header = Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id="")
                    state = JointState(header=header, name=names, position=zeros.copy(),
                                       velocity=velocity[k].copy() if velocity is not None else zeros.copy(),
                                       effort=effort[k].copy())
                    writer.write(states, ns, store.serialize_cdr(state, JointState.__msgtype__))
                    if thermal is not None:
                        heat = Thermal(name=names, temperature=temperature[k].copy(),
                                       current=current[k].copy() if current is not None else empty,
                                       housing=housing[k].copy() if housing is not None else empty)
                        writer.write(thermal, ns, store.serialize_cdr(heat, THERMAL_TYPE))
                    if dynamic is not None and k % temperature_every == 0:
                        values = [Interface(interface_names=list(interfaces), values=stacked[k, j].copy())
                                  for j in range(len(names))]
                        msg = Dynamic(header=header, joint_names=names, interface_values=values)
                        writer.write(dynamic, ns, store.serialize_cdr(msg, DYNAMIC_TYPE))
                    for j, conn in enumerate(joints if k % temperature_every == 0 else ()):
                        msg = TemperatureMsg(header=header, temperature=float(temperature[k, j]),
                                             variance=0.0)
                        writer.write(conn, ns, store.serialize_cdr(msg, TemperatureMsg.__msgtype__))
                    if air is not None:
                        msg = TemperatureMsg(header=header, temperature=float(ambient[k, 0]), variance=0.0)
                        writer.write(air, ns, store.serialize_cdr(msg, TemperatureMsg.__msgtype__))
            shutil.move(str(next(folder.glob("*.mcap"))), tmp)
        finally:
            shutil.rmtree(folder.parent, ignore_errors=True)
    return path

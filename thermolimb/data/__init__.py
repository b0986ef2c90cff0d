"""Data shipped with the suite (real motor measurements, with provenance and licence)."""

from __future__ import annotations

from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path

from ..util.errors import UsageError

PMSM_MAP = (
    "time=time,effort=torque,velocity=motor_speed,temperature=stator_winding,ambient=coolant,current=current"
)
# the columns' units as the dataset's README states them (its header has none); the velocity is converted to
# rad/s
PMSM_UNITS = {"effort_unit": "N m", "velocity_unit": "rpm"}


def pmsm_profile(number: int) -> Path:
    """Path of the bundled PMSM test-bench profile 24 or 46 (see data/pmsm/README.md)."""
    path = Path(str(files(__package__) / "pmsm" / f"profile{number}.csv"))
    if not path.is_file():
        raise UsageError(f"no bundled PMSM profile {number}; there are profiles 24 and 46")
    return path


REAL_DIR = Path(str(files(__package__) / "real"))


@dataclass(frozen=True)
class RealLog:
    """A bundled real log: its files (runs of the same actuators) and the options that read it."""

    name: str
    files: tuple[str, ...]
    mapping: str
    actuator: str | None = None
    drop_incomplete: bool = False
    description: str = ""

    @property
    def paths(self) -> list[Path]:
        return [REAL_DIR / f for f in self.files]

    def read(self) -> list:
        """The logs, read as ``thermolimb`` reads them with these options."""
        from ..logs import parse_mapping, read_log

        return [read_log(p, mapping=parse_mapping(self.mapping), actuator_name=self.actuator,
                         drop_incomplete=self.drop_incomplete) for p in self.paths]


REAL_LOGS = {
    log.name: log
    for log in (
        RealLog(
            "ur3",
            ("ur3-cobotops/dataset_02052023.csv",),
            "time=Timestamp,effort=Current_J{j},temperature=Temperature_*{j},velocity=Speed_J{j}",
            drop_incomplete=True,
            description="UR3 cobot, six joints, 1 Hz, two parts 5.2 h apart",
        ),
        RealLog(
            "wx200",
            ("interbotix-wx200/wx200_ext_bearing.csv", "interbotix-wx200/wx200_home_bearing.csv"),
            "time=States Time [s],effort=Effort [mA],temperature=Temp [C],velocity=Velocity [rad/s]",
            actuator="waist",
            description="WidowX-200 waist servo, two 600 s runs, whole degrees",
        ),
        RealLog(
            "bldc",
            ("tass-bldc-bench/Run2-Throttle100_unified.csv", "tass-bldc-bench/Run13-Throttle8_unified.csv"),
            "time=Time (s),effort=Power (W),power=Power (W),temperature=Winding Temp (°C)",
            actuator="bldc",
            description="BLDC bench, two heating runs of 2-2.5 min at 10 Hz",
        ),
    )
}

# A hobby motor's thermocouple logs as the lab's Arduino wrote them (the first day's without a header row):
# ten runs whose sensor reads low while the motor is driven, which fit and diagnose refuse, naming the
# intervals.
# the first day's, unwritten
GIMBALBOT_COLUMNS = ("timeSinceStart", "pwmOut", "tempCelsius", "tempRefCelsius")
GIMBALBOT = RealLog(
    "gimbalbot",
    tuple(
        f"gimbalbot-esc-motor/test01262015-0{k}-{kind}.csv"
        for k, kind in (
            (1, "control"),
            (2, "control"),
            (3, "control"),
            (4, "justnozzles"),
            (5, "justnozzles"),
            (6, "justnozzles"),
            (7, "3x8venturi"),
        )
    ),
    "time=timeSinceStart:ms,effort=pwmOut,temperature=tempCelsius,ambient=tempRefCelsius",
    actuator="motor",
    drop_incomplete=True,
    description="hobby BLDC on an ESC, thermocouple disturbed while driven",
)

# The same 106 s WidowX-200 run twice: the ROS 1 bag as recorded, and the package's CSV export of it
# (three time bases, each from zero at its own first sample).
WX200_BAG = RealLog("wx200-bag", ("interbotix-wx200/waist_diagnostics.bag",), "", actuator="waist",
                    description="WidowX-200 waist, ROS 1 bag: joint states 100 Hz, temperatures every 5 s")
WX200_EXPORT = RealLog("wx200-export", ("interbotix-wx200/waist_diagnostics.csv",),
                       "temperature=Temp [C]@Temperature Time [s],effort=Effort [mA]@States Time [s],"
                       "velocity=Velocity [rad/s]@States Time [s]", actuator="waist",
                       description="the same run as the package's CSV export")

"""Data shipped with the suite (real motor measurements, with provenance and licence)."""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

PMSM_MAP = "time=time,effort=torque,velocity=motor_speed,temperature=stator_winding,ambient=coolant,current=current"


def pmsm_profile(number: int) -> Path:
    """Path of the bundled PMSM test-bench profile 24 or 46 (see data/pmsm/README.md)."""
    path = Path(str(files(__package__) / "pmsm" / f"profile{number}.csv"))
    if not path.is_file():
        raise FileNotFoundError(f"no bundled PMSM profile {number}; there are profiles 24 and 46")
    return path

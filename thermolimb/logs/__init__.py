"""Thermal logs: the canonical tidy format, reading real files, validation.

Canonical log (long format, one row per actuator and sample), CSV or Parquet:

===============  =======================================  ==========
column           unit                                     required
===============  =======================================  ==========
``time``         s (or timestamps: seconds from the first)  yes
``actuator``     name                                     yes
``effort``       N m (rotary) or N                        yes
``temperature``  degC, as measured                        yes
``velocity``     rad/s or m/s                             no
``current``      A                                        no
``power``        W, electrical input                      no
``ambient``      degC                                     no
``housing``      degC, a second sensor (housing, case)    no
===============  =======================================  ==========

The data (:mod:`.series`) is apart from reading (:mod:`.reading`, one
place per format), validating (:mod:`.validate`) and writing (:mod:`.writing`).
Wide files (a motor bench, a robot's joints side by side) are read by naming
their columns (:mod:`thermolimb.logs.mapping`); the CSV dialect, a metadata
preamble and the time format are found from the file (:mod:`thermolimb.logs.table`).
Every problem with a file raises :class:`LogError` with one sentence naming the
file, the column and what is expected.
"""

from ..util.errors import LogError
from .mapping import OPTIONAL, REQUIRED, UNITS, parse_mapping
from .reading import read_log
from .series import GAP_FACTOR, GAP_MIN_S, MIN_SAMPLES, ActuatorSeries, ThermalLog, gaps
from .validate import VELOCITY_UNITS, from_frame, log_from_arrays
from .writing import write_pieces

__all__ = ["ActuatorSeries", "GAP_FACTOR", "GAP_MIN_S", "LogError", "MIN_SAMPLES", "OPTIONAL", "REQUIRED",
           "ThermalLog", "UNITS", "VELOCITY_UNITS", "from_frame", "gaps", "log_from_arrays", "parse_mapping",
           "read_log", "write_pieces"]

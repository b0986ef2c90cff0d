"""The model a walk on one run ends with must survive the run's head (issue 81, item 6): the reversed split.

The log: a first-order plant (random holds and motions, 0.05 K noise, 0.1 degC steps) whose housing carries a
Peltier element, its drive (+1 heats, -1 cools) logged as ``peltier``, switched every 6 minutes all run long;
the element is wired only after the run's first quarter (``WIRED``), so in the head the drive moves and no heat
follows.  The term that reads the drive is a user's (``--terms``), the truth's own form: this shows that the
run's head refutes a change its tail supports, not that the search finds the form.  Over the plant's seeds 0-3
(:func:`peltier_log`'s ``seed``) the change is refuted on 0, 2 and 3; on seed 1 the model without it, fitted on
the tail alone, misses the head by 1.37 K itself, and the change is taken.
"""

from __future__ import annotations

import json
import re
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from conftest import first_order_log
from scipy.signal import lfilter

from thermolimb.logs import from_frame
from thermolimb.workbench.diagnosis import auto_diagnose, diagnose
from thermolimb.workbench.diagnosis.reversed_split import REFUTED_SHARE, walk_cut
from thermolimb.workbench.validation import Scheme

TERM = textwrap.dedent('''
    from thermolimb.model import LinearTerm, Parameter, register_term


    @register_term
    class PeltierHeat(LinearTerm):
        """A Peltier element's heat, in proportion to its logged drive."""

        name = "peltier_heat"
        description = "a Peltier element's heat, in proportion to its drive"
        columns = ("extra.peltier",)
        parameters = (Parameter("peltier_K", "K", -20.0, 20.0, 1.0, "kelvin of rise at full drive"),)

        def regressor(self, s):
            return s.channel("extra.peltier")
''')
RISE_K = 2.0
PERIOD_SHARE = 0.05  # of the run: six minutes of a two-hour run
RC_S = 80.0  # the plant's winding (conftest's first-order X8)


def peltier_log(wired: float, seed: int = 0):
    """The two-hour log (module docstring), the element wired from ``wired`` of the run on."""
    frame = first_order_log(seed, duration_s=7200.0).frame.drop(columns=["ambient"])
    t = frame["time"].to_numpy()
    u = (t - t.min()) / np.ptp(t)
    drive = 2.0 * (np.floor(u / PERIOD_SHARE) % 2) - 1.0
    a = np.exp(-1.0 / RC_S)
    heat = lfilter([1.0 - a], [1.0, -a], np.where(u < wired, 0.0, drive))
    frame["temperature"] = np.round(frame["temperature"] + RISE_K * heat, 1)
    frame["peltier"] = drive
    return frame


@pytest.fixture()
def peltier_term():
    namespace: dict = {}
    exec(TERM, namespace)  # noqa: S102 -- the same source the command line loads with --terms
    return namespace["PeltierHeat"]


def test_a_walk_the_tail_supports_and_the_head_refutes_steps_back(peltier_term):
    run = from_frame(peltier_log(wired=0.25)).series("knee")
    first, steps = auto_diagnose([run], stability=None)
    last = steps[-1]
    change = last.unstable
    assert last.recommended is None and change is not None and change.effect == "peltier_heat"
    assert change.helps and change.status == "refuted"
    assert "peltier_heat" not in last.model and [s.get("change") for s in first.auto][-1] != "+ peltier_heat"
    said = change.refuted_because
    assert said.startswith("refuted by the run's first 30 %: fitted on its last 70 %, the model with it (")
    after, before = (float(x) for x in re.findall(r"at ([0-9.]+) K", said))
    assert after > (1.0 + REFUTED_SHARE) * before and after - before > first.floor.floor_K
    # the stage alone, on the walk as it went before the step back, says the same
    walked = steps + [diagnose([run], change.model, stability=None)]
    assert walk_cut(walked, [run], Scheme.at_split(0.7), first.floor) == (len(steps) - 1, said)


def test_a_change_that_holds_over_the_whole_run_is_not_refuted(peltier_term):
    run = from_frame(peltier_log(wired=0.0)).series("knee")
    first, steps = auto_diagnose([run], stability=None)
    assert "+ peltier_heat" in [s.get("change") for s in first.auto]
    assert all(d.unstable is None or d.unstable.refuted_because is None for d in steps)


def test_the_command_line_says_the_change_is_refuted_and_the_walk_stops(tmp_path):
    peltier_log(wired=0.25).to_csv(tmp_path / "run.csv", index=False)
    (tmp_path / "peltier.py").write_text(TERM)
    common = [sys.executable, "-m", "thermolimb", "diagnose", str(tmp_path / "run.csv"), "--actuator", "knee",
              "--terms", str(tmp_path / "peltier.py"), "--auto", "--stability", "0"]
    text = subprocess.run(common, capture_output=True, text=True, check=True).stdout
    assert "+ peltier_heat helps" in text and "but is refuted by the run's first 30 %" in text
    assert "the walk stops before it" in text
    record = json.loads(subprocess.run(common + ["--json"], capture_output=True, text=True, check=True).stdout)
    step = record["auto"][-1]
    assert step["unstable"]["status"] == "refuted" and step["unstable"]["change"] == "+ peltier_heat"
    assert next(c for c in record["candidates"] if c["effect"] == "peltier_heat")["status"] == "refuted"

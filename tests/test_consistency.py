"""One story: what ``diagnose --auto`` prints, its JSON and its candidates figure come from one record.

On every bundled real log (and a plant log like the demos'), the text of a diagnosis is checked against the
JSON of the same diagnosis:

* every number in the text is a number of the JSON (to the precision printed, or as a percentage), or
  sits in a sentence the JSON carries word for word;
* every sentence that names a value (``RC_s = 25.7 ± 16 s``) names the value and standard error of the
  record it belongs to: the base model for the base's flags, the candidate's own refitted model for its
  evidence (a candidate's RC_s is not the base's);
* a candidate's "validation RMSE goes from A K to B K" has A = the base's, B = its own;
* an evidence sentence never calls a correlation insignificant for a change that helps;
* every candidate not refitted, or whose refit failed, says why in its text line, its JSON and the figure.
"""

from __future__ import annotations

import bisect
import math
import re

import matplotlib
import pytest

matplotlib.use("Agg")

from thermolimb.cli.diagnose import describe_diagnosis  # noqa: E402
from thermolimb.data import PMSM_MAP, REAL_LOGS, WX200_BAG, WX200_EXPORT, pmsm_profile  # noqa: E402
from thermolimb.logs import read_log  # noqa: E402
from thermolimb.model.terms import readable  # noqa: E402
from thermolimb.plant import NETWORKS, X8_9, PlantEffects, simulate_profile  # noqa: E402
from thermolimb.plotting.diagnosis import candidates_figure  # noqa: E402
from thermolimb.workbench.diagnosis import auto_diagnose  # noqa: E402

NUMBER = re.compile(r"(?<![\w.^/])([-+−]?)(\d+(?:\.\d+)?)(?:e([-+]?\d+))?(?![\w^])", re.I)
NAMED = re.compile(r"\b([A-Za-z][\w]*_[\w]*) = ([-+]?\d[\d.]*(?:e[-+]?\d+)?)(?: ± (\d[\d.]*(?:e[-+]?\d+)?))?")


def _numbers(text: str):
    """``(token, value, half a unit of its last printed digit)`` for each number printed in ``text``."""
    for m in NUMBER.finditer(text):
        sign, mantissa, exponent = m.groups()
        decimals = len(mantissa.partition(".")[2])
        e = int(exponent or 0)
        yield m.group(0), float(mantissa) * 10.0**e * (-1 if sign in ("-", "−") else 1), 0.5 * 10.0 ** (e - decimals)


def _agrees(printed: str, value: float) -> bool:
    """``printed`` is ``value`` to the precision it is printed at (``%g``, fixed or scientific)."""
    [(_, shown, half)] = list(_numbers(printed))
    return abs(shown - value) <= half * (1 + 1e-9) + 1e-12 * abs(value)


def _leaves(obj, numbers: list, strings: list):
    if isinstance(obj, bool) or obj is None:
        return
    if isinstance(obj, (int, float)):
        if math.isfinite(obj):
            numbers.append(float(obj))
    elif isinstance(obj, str):
        strings.append(obj)
    elif isinstance(obj, dict):
        for v in obj.values():
            _leaves(v, numbers, strings)
    elif isinstance(obj, (list, tuple)):
        for v in obj:
            _leaves(v, numbers, strings)


def unmatched_numbers(text: str, record: dict) -> list[str]:
    """Numbers in ``text`` that are neither a JSON number nor inside a sentence the JSON holds verbatim."""
    numbers, strings = [], []
    _leaves(record, numbers, strings)
    for sentence in sorted({s for s in strings if len(s) > 12}, key=len, reverse=True):
        text = text.replace(sentence, " ")
    values = sorted({w for v in numbers for w in (v, -v, 100 * v, -100 * v)})
    out = []
    for token, value, half in _numbers(text):
        i = bisect.bisect_left(values, value - half * (1 + 1e-9))
        if not (i < len(values) and values[i] <= value + half * (1 + 1e-9)):
            out.append(token)
    return out


def misnamed_values(sentences: list[str], params: dict, stderr: dict | None = None) -> list[str]:
    """``NAME = value ± se`` in ``sentences`` where NAME is a parameter of ``params`` and the value disagrees."""
    bad = []
    for sentence in sentences:
        for name, value, se in NAMED.findall(sentence):
            if name not in params:
                continue
            if not _agrees(value, params[name]):
                bad.append(f"{name} = {value} (record: {params[name]:.6g}) in: {sentence}")
            if se and stderr and name in stderr and not _agrees(se, stderr[name]):
                bad.append(f"{name} ± {se} (record: {stderr[name]:.6g}) in: {sentence}")
    return bad


def check_one_story(d) -> int:
    """Every check of the module docstring on one diagnosis; returns how many numbers were checked."""
    text, record = describe_diagnosis(d), d.to_json()
    assert not unmatched_numbers(text, record), (unmatched_numbers(text, record), text)
    base = {k: v["value"] for k, v in record["base_params"].items()}
    base_se = {k: v["stderr"] for k, v in record["base_params"].items()}
    assert not misnamed_values(record["flags"] + [record["evidence"]["sentence"]], base, base_se)
    for step in record.get("auto", [])[1:]:
        assert _agrees(re.search(r"-> ([\d.]+) K", step["why"]).group(1), step["rmse_K"]), step
    lines = text.splitlines()
    for c in record["candidates"]:
        own = c["model_params"] or {}
        assert not misnamed_values([c["evidence"], c["failure"] or "", c["implausible_because"] or ""],
                                   {**base, **own} if own else base), c["label"]
        move = re.search(r"validation RMSE goes from ([\d.]+) K to ([\d.]+) K", c["evidence"])
        if move:
            assert _agrees(move.group(1), record["base"]["rmse_K"]) and _agrees(move.group(2), c["rmse_K"])
        if c["status"] == "helps":
            assert "does not correlate significantly" not in c["evidence"], c["evidence"]
        if c["rmse_K"] is None or c["failure"]:
            reason = (c["failure"] or c["not_judged"] or c["confounded"] or c.get("skipped")
                      or f"p = {c['p_value']:.2g}")
            assert reason, c["label"]
            assert any(c["label"] in line and (reason in line or reason.split(":")[0] in line) for line in lines) \
                or reason in c["evidence"], (c["label"], reason)
    figure = candidates_figure(d)
    drawn = " ".join(t.get_text() for t in figure.texts + [t for ax in figure.axes for t in ax.texts])
    for c in d.candidates:
        if c.failure:
            assert c.failure in drawn, (c.label, c.failure)
        elif not c.refitted:  # named in words, with its identifier beside them
            assert readable(c.label) in drawn, c.label
    matplotlib.pyplot.close(figure)
    return len(list(_numbers(text)))


def _bundled():
    logs = {log.name: log for log in (*REAL_LOGS.values(), WX200_BAG, WX200_EXPORT)}
    return logs


def _series(logs, actuator):
    return [run for log in logs for run in log.runs(actuator)]


def test_the_checker_catches_a_number_the_record_does_not_hold():
    """The test's own teeth: a changed digit, a base value put in a candidate's sentence, an insignificant
    correlation given as the reason for a change that helps."""
    record = {"base": {"rmse_K": 0.599}, "flags": ["RC_s = 25.7 ± 16 s: uncertain"]}
    assert unmatched_numbers("validation RMSE 0.599 K (-14.8 %)", {**record, "gain": -0.148}) == []
    assert unmatched_numbers("validation RMSE 0.598 K", record) == ["0.598"]
    assert misnamed_values(["frame_tau_s = 10.1 s is not slower than RC_s = 10.1 s"],
                           {"RC_s": 25.675, "frame_tau_s": 10.14}) == [
        "RC_s = 10.1 (record: 25.675) in: frame_tau_s = 10.1 s is not slower than RC_s = 10.1 s"]
    assert misnamed_values(["RC_s = 25.7 ± 16 s"], {"RC_s": 25.675}, {"RC_s": 19.0})


@pytest.fixture(scope="module")
def plant_diagnosis():
    """A plant log with a hidden effect, as the diagnose demo makes (a slow housing node)."""
    run = simulate_profile("squat", 1800.0, 1.0, ["knee"], [X8_9],
                           PlantEffects.from_names(["sensor_noise", "quantisation"]), seed=3,
                           network=NETWORKS["second_order"])
    return auto_diagnose([run.log.series("knee")])[0]


def test_a_plant_diagnosis_tells_one_story(plant_diagnosis):
    assert check_one_story(plant_diagnosis) > 40


@pytest.mark.parametrize("name", ["wx200-bag", "bldc"])
def test_short_real_logs_tell_one_story(name):
    logs = _bundled()[name].read()
    for actuator in logs[0].actuators:
        first, _ = auto_diagnose(_series(logs, actuator))
        assert check_one_story(first) > 30


@pytest.mark.slow
@pytest.mark.parametrize("name", ["ur3", "wx200", "wx200-export", "pmsm24", "pmsm46"])
def test_every_bundled_real_log_tells_one_story(name):
    if name.startswith("pmsm"):
        logs = [read_log(pmsm_profile(int(name[4:])), mapping=PMSM_MAP, actuator_name="pmsm")]
    else:
        logs = _bundled()[name].read()
    for actuator in logs[0].actuators:
        first, _ = auto_diagnose(_series(logs, actuator))
        check_one_story(first)


def test_thin_evidence_recommends_nothing_and_says_so():
    """The WidowX bag holds 6 held-out temperature readings: nothing is recommended, and the text says why."""
    logs = WX200_BAG.read()
    first, steps = auto_diagnose(_series(logs, "waist"))
    assert first.base.evidence.samples < 10 and first.recommended is None and len(steps) == 1
    text = describe_diagnosis(first)
    assert "too thin" in text and f"evidence: {first.base.evidence.samples} validation samples" in text
    assert first.to_json()["evidence"]["verdict"] == "too thin"

"""Units come from the log, never assumed: headers, mappings and options carry them into every parameter's unit."""

import numpy as np
import pandas as pd
import pytest

from thermolimb.logs import from_frame, read_log
from thermolimb.logs.units import NOT_GIVEN, header_unit, split_unit
from thermolimb.model.parameter_units import render
from thermolimb.workbench.validation import Scheme, validate_model


def bench(n=400, seed=0):
    """A motor bench with a current logged in mA, a speed in rpm, and a temperature that follows the current."""
    rng = np.random.default_rng(seed)
    t = np.arange(n, dtype=float)
    current = np.repeat(rng.choice([0.0, 400.0, 800.0, 1200.0], n // 40), 40)[:n]
    temperature = 25.0 + np.convolve(2e-5 * current**2, np.exp(-np.arange(200) / 30.0) / 30.0)[:n]
    return pd.DataFrame({"Time [s]": t, "Effort [mA]": current, "Speed [rpm]": 60.0 + 0 * t, "Current_A1": current,
                         "Temp [C]": temperature + rng.normal(0, 0.02, n)})


@pytest.mark.parametrize("column, unit", [("Effort [mA]", "mA"), ("Power (W)", "W"), ("Current_J1", None),
                                          ("Temp [C]@Temperature Time [s]", "C"), ("Speed_J1 [rad/s]", "rad/s")])
def test_a_header_gives_its_unit(column, unit):
    assert header_unit(column) == unit


def test_a_mapping_may_name_a_unit_after_a_colon_and_a_column_keeps_its_own_colons():
    assert split_unit("Current_J{j}:A") == ("Current_J{j}", "A")
    assert split_unit("Time: since start") == ("Time: since start", None)


def test_rendering_says_when_a_unit_was_not_given():
    assert render("K/({effort})^2", {"effort": "N m"}) == "K/(N m)^2"
    assert render("K/({effort})^2", {"effort": "mA"}) == "K/mA^2"
    assert render("K/({velocity})", {"velocity": "rad/s"}) == "K/(rad/s)"
    assert render("K/({effort})^2", {"effort": NOT_GIVEN}) == "K/(effort: unit not given)^2"
    assert render("s", {}) == "s"


def test_units_travel_from_the_header_to_every_parameter():
    log = from_frame(bench(), mapping={"time": "Time [s]", "effort": "Effort [mA]", "temperature": "Temp [C]",
                                       "velocity": "Speed [rpm]"}, actuator_name="motor")
    assert dict(log.units) == {"effort": "mA", "velocity": "rad/s", "current": NOT_GIVEN, "power": NOT_GIVEN,
                               "extra.Current_A1": NOT_GIVEN}  # the unmapped column, kept as an extra channel
    np.testing.assert_allclose(log.frame["velocity"], 60.0 * 2 * np.pi / 60.0)  # rpm from the header, converted
    record = validate_model([log.series("motor")], "joule", Scheme()).to_json()
    assert record["params"]["betaR_K_per_effort2"]["unit"] == "K/mA^2"
    assert record["channel_units"]["effort"] == "mA"


def test_a_column_without_a_unit_is_reported_as_not_given_and_the_mapping_or_an_option_can_give_it():
    mapping = {"time": "Time [s]", "effort": "Current_A1", "temperature": "Temp [C]"}
    assert from_frame(bench(), mapping=mapping).units["effort"] == NOT_GIVEN
    assert from_frame(bench(), mapping={**mapping, "effort": "Current_A1:A"}).units["effort"] == "A"
    assert from_frame(bench(), mapping=mapping, units={"effort": "A"}).units["effort"] == "A"


def test_the_canonical_format_is_in_its_documented_units(plant_log):
    assert dict(plant_log.units) == {"effort": "N m", "velocity": "rad/s", "current": "A", "power": "W"}
    record = validate_model([plant_log.series("knee")], "joule,effort_bias", Scheme()).to_json()
    assert record["params"]["betaR_K_per_effort2"]["unit"] == "K/(N m)^2"


def test_a_bag_says_its_effort_unit_was_not_given_unless_told():
    from thermolimb.data import WX200_BAG

    BAG = WX200_BAG.paths[0]
    assert read_log(BAG, actuator_name="waist").units["effort"] == NOT_GIVEN
    assert read_log(BAG, actuator_name="waist", effort_unit="mA").units["effort"] == "mA"


def test_an_implausible_value_is_said_in_the_unit_its_log_gives_and_a_one_argument_term_is_still_asked():
    from thermolimb.model.terms import TERMS, Term, implausibility

    motion = TERMS["motion_cooling"]()
    said = implausibility(motion, {"cooling_per_rad_s": 9.0}, {"velocity": "rad/s"})
    assert said == "cooling_per_rad_s = 9 1/(rad/s) is outside 0..5"
    assert implausibility(motion, {"cooling_per_rad_s": 1.0}, {"velocity": "rad/s"}) is None

    class Written(Term):  # a user's term written before terms took units
        name = "written_before"
        def implausible(self, p):
            return "too hot" if p["x"] > 1 else None

    assert implausibility(Written(), {"x": 2.0}, {"velocity": "rad/s"}) == "too hot"

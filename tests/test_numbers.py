"""Numbers in sentences: significant figures without an exponent a reader has to decode."""

import math

from hypothesis import given
from hypothesis import strategies as st

from thermolimb.util.numbers import places3, plus_minus, significant
from thermolimb.workbench.floor import SensorFloor


def test_a_standard_error_in_the_hundreds_is_written_out():
    # format(360.4, ".2g") is "3.6e+02": what the flags printed before
    assert significant(360.4) == "360"
    assert plus_minus(261.0, 360.4) == "261 ± 360"
    assert plus_minus(0.000422, 0.00052) == "0.000422 ± 0.00052"
    assert significant(2.5e7) == "2.5e+07"  # an exponent where writing out would mislead about the digits


@given(st.floats(min_value=-1e9, max_value=1e9, allow_nan=False).filter(lambda x: x == 0 or abs(x) > 1e-12),
       st.integers(min_value=1, max_value=6))
def test_significant_reads_back_as_the_value_to_its_digits(x, digits):
    text = significant(x, digits)
    back = float(text)
    # rounding to `digits` significant figures moves a value by at most half a unit in its last place
    assert math.isclose(back, x, rel_tol=10.0 ** (1 - digits), abs_tol=1e-300)
    if "e" in text:
        assert abs(back) >= 1e6 or back != round(back) or abs(back) < 1e-4


def test_a_floor_under_a_hundredth_of_a_kelvin_is_not_written_as_none():
    """A smooth thermistor's noise floor (0.00021 K) read "a 0.000 K noise floor" and "sensor's floor, 0.000 K"."""
    assert places3(0.061) == "0.061" and places3(0.2894) == "0.289" and places3(0.0) == "0.000"
    assert places3(0.00021) == "0.00021" and places3(0.0039) == "0.0039"
    assert "against a 0.00021 K noise floor" in SensorFloor(0.0, 0.0, 0.00021).sentence(0.5)

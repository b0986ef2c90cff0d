"""Numbers in sentences: significant figures without an exponent a reader has to decode."""

import math

from hypothesis import given
from hypothesis import strategies as st

from thermolimb.util.numbers import plus_minus, significant


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

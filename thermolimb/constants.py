"""Physical constants the whole suite shares, each written once."""

COPPER_TEMPCO_PER_K = 0.0039  # copper's resistance rises 0.39 % per kelvin
# the temperature a winding's resistance is quoted at (ActuatorSpec.winding_resistance_ohm)
COPPER_REFERENCE_C = 25.0
GRAVITY_M_S2 = 9.81  # standard gravity, as PyBullet's worlds and the robots' statics use it

"""Physical constants the whole suite shares, each written once."""

GRAVITY_M_S2 = 9.81  # standard gravity, as PyBullet's worlds and the robots' statics use it

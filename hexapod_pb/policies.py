"""The hexapod's strategies as policies of ``thermolimb/HexapodLoadCarry-v0``.

``vertical_only``, ``minimax`` and ``thermal_aware`` put full weight on that
stance-force distribution and walk at full speed (``random`` comes from the
core).
"""

from __future__ import annotations

import numpy as np

from thermolimb.envs.policies import constant_policy

POLICIES = {
    name: constant_policy(np.array(action, dtype=np.float32))
    for name, action in (
        ("vertical_only", [1, 0, 0, 1]),
        ("minimax", [0, 1, 0, 1]),
        ("thermal_aware", [0, 0, 1, 1]),
    )
}

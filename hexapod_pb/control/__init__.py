"""Control: the CPG tripod gait, the hybrid motion-force controller (Nair et al.'s Eq. 6, a pure function),
the one control loop every run steps, and the stance-wrench distribution (the problem, the exact minimax, the
thermal minimax, Nair et al.'s own solver)."""

"""hexapod_pb: a Daisy-like 18-actuator hexapod in PyBullet, CPG tripod gait, hybrid motion-force control
with minimax-optimised stance wrenches, and thermal load carrying."""

"""hexapod_pb: a Daisy-like 18-actuator hexapod in PyBullet, CPG tripod gait, hybrid motion-force control
with minimax-optimised stance wrenches, and thermal load carrying."""

from thermolimb.envs import register_env

ENV_ID = "thermolimb/HexapodLoadCarry-v0"
register_env(ENV_ID, "hexapod_pb.env:HexapodLoadCarryEnv", policies="hexapod_pb.policies")

"""humanoid_pb: a Valkyrie-like humanoid in PyBullet; contact-constrained thermal inverse kinematics and
contact switching to recover hot actuators, against a minimum-effort strategy (Jorgensen et al., on
Valkyrie)."""

from thermolimb.envs import register_env

ENV_ID = "thermolimb/HumanoidThermalRecovery-v0"
register_env(ENV_ID, "humanoid_pb.env:HumanoidThermalRecoveryEnv", policies="humanoid_pb.policies")

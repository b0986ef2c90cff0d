"""humanoid_pb: a Valkyrie-like humanoid in PyBullet; contact-constrained thermal inverse kinematics and
contact switching to recover hot actuators, against a minimum-effort strategy (the Valkyrie seed)."""

"""The humanoid's model: its generated URDF, whole-body statics with Pinocchio (Jorgensen et al.'s Eqs.
18-24), and how joint torques become actuator efforts (motors, and the push-rod pairs of the ankles and
waist)."""

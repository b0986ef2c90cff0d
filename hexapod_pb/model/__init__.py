"""The hexapod's model: its generated URDF (Daisy-like), the legs' kinematics and each leg's Jacobian, mass
matrix and gravity torques."""

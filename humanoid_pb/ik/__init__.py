"""Finding configurations: the thermal potential (Jorgensen et al.'s Eqs. 25-26), their descent (kept to
compare), the fast thermal IK with every constraint, the same on their own objective, and the nominal
poses."""

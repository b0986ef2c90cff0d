"""Experiments on the humanoid: the calibration run, Jorgensen et al.'s recovery experiment, and the map of where
contact switching pays."""

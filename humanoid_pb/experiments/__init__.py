"""Experiments on the humanoid: Jorgensen et al.'s recovery experiment, and the map of where
contact switching pays."""

"""Experiments on the hexapod: Nair et al.'s load-carrying scenarios, and the endurance envelope (how long it
works before an actuator derates)."""

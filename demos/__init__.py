"""Demos of the suite; each module registers itself with thermolimb.demo_registry."""

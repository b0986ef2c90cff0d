"""Every figure the suite draws: static Matplotlib plots of fits and diagnoses, and self-contained interactive
pages."""

"""The ``thermolimb`` command line."""

"""Demos of the suite, installed as ``thermolimb_demos``; each module registers itself with
``thermolimb.demo_registry`` and is listed in the ``thermolimb.demos`` entry-point group (``setup.cfg``)."""

"""thermolimb: thermal-aware control of multi-limbed robots in PyBullet.

Importing the package loads nothing heavy: no Gymnasium, no PyBullet, no
environments.  The robots' environments register when their package is
imported (``import hexapod_pb``, ``import humanoid_pb``).
"""

from . import effects  # noqa: F401  (registers the catalog's terms and the plant's effects)
from .util.paths import urdf_dir

__version__ = "0.1.0"
__all__ = ["__version__", "urdf_dir"]

"""thermolimb: thermal-aware control of multi-limbed robots in PyBullet."""

from .envs import register_envs
from .paths import urdf_dir

register_envs()

__version__ = "0.1.0"
__all__ = ["__version__", "urdf_dir"]

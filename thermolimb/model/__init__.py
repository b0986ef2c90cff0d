"""The effort-based thermal model of Jorgensen et al. (Eqs. 5, 6, 17, 25), composable terms.

The built-in terms are the physical effects of :mod:`thermolimb.effects`, registered when ``thermolimb`` is
imported.
"""

from .arrays import ModelArrays
from .model import BASE_PARAMETERS, ThermalModel, model_parameters
from .saved import load_model, save_model
from .scan import first_order_scan
from .signals import Signals
from .terms import (
                    DEFAULT_MODEL,
                    TERMS,
                    LinearTerm,
                    ModelSpecError,
                    Parameter,
                    Term,
                    parse_model,
                    register_term,
                    unregister_term,
)

__all__ = [
    "BASE_PARAMETERS",
    "DEFAULT_MODEL",
    "ModelArrays",
    "LinearTerm",
    "ModelSpecError",
    "Parameter",
    "Signals",
    "TERMS",
    "Term",
    "ThermalModel",
    "first_order_scan",
    "load_model",
    "model_parameters",
    "parse_model",
    "register_term",
    "save_model",
    "unregister_term",
]

"""The effort-based thermal model of Jorgensen et al. (Eqs. 5, 6, 17, 25), composable terms."""

from . import catalog  # noqa: F401  (registers the built-in terms)
from .bank import FirstOrderBank
from .model import BASE_PARAMETERS, ThermalModel, model_parameters
from .scan import first_order_scan
from .signals import Signals
from .terms import DEFAULT_MODEL, TERMS, ModelSpecError, Parameter, Term, parse_model, register_term, unregister_term

__all__ = [
    "BASE_PARAMETERS", "DEFAULT_MODEL", "FirstOrderBank", "ModelSpecError", "Parameter", "Signals",
    "TERMS", "Term", "ThermalModel", "first_order_scan", "model_parameters", "parse_model", "register_term",
    "unregister_term",
]

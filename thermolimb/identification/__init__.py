"""Identification of the thermal model from logs: three methods behind one estimator contract."""

from ..util.errors import IdentifiabilityError
from .base import ThermalEstimator
from .jorgensen_gd import JorgensenGradientDescent
from .least_squares import LeastSquares
from .output_error import FreeRunLeastSquares
from .regression import build_regression

ESTIMATORS = {
    "jorgensen_gd": JorgensenGradientDescent,
    "least_squares": LeastSquares,
    "output_error": FreeRunLeastSquares,
}

__all__ = [
    "ESTIMATORS",
    "IdentifiabilityError",
    "LeastSquares",
    "FreeRunLeastSquares",
    "JorgensenGradientDescent",
    "ThermalEstimator",
    "build_regression",
]

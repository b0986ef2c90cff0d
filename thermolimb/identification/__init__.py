"""Identification of the thermal model from logs: three methods behind one estimator contract."""

from .base import ThermalEstimator
from .least_squares import LeastSquares
from .output_error import OutputError
from .regression import IdentifiabilityError, build_regression
from .jorgensen_gd import JorgensenGradientDescent

ESTIMATORS = {
    "jorgensen_gd": JorgensenGradientDescent,
    "least_squares": LeastSquares,
    "output_error": OutputError,
}

__all__ = ["ESTIMATORS", "IdentifiabilityError", "LeastSquares", "OutputError", "JorgensenGradientDescent",
           "ThermalEstimator", "build_regression"]

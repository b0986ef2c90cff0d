"""Identification of the thermal model from logs: three methods behind one estimator contract."""

from .base import ThermalEstimator
from .least_squares import LeastSquares
from .output_error import OutputError
from .regression import IdentifiabilityError, build_regression
from .seed_gd import SeedGradientDescent

ESTIMATORS = {
    "seed_gd": SeedGradientDescent,
    "least_squares": LeastSquares,
    "output_error": OutputError,
}

__all__ = ["ESTIMATORS", "IdentifiabilityError", "LeastSquares", "OutputError", "SeedGradientDescent",
           "ThermalEstimator", "build_regression"]

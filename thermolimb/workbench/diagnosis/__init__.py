"""Model versus measurement: where the model fails, which effect is missing."""

from .candidates import Candidate
from .diagnose import Diagnosis, Search, auto_diagnose, diagnose
from .residuals import ResidualAnalysis, analyse_residuals

__all__ = [
    "Candidate",
    "Diagnosis",
    "ResidualAnalysis",
    "Search",
    "analyse_residuals",
    "auto_diagnose",
    "diagnose",
]

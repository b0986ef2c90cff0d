"""Model versus measurement: where the model fails, which effect is missing."""

from .candidates import Candidate
from .diagnose import Diagnosis, auto_diagnose, diagnose
from .residuals import ResidualAnalysis, analyse_residuals

__all__ = ["Candidate", "Diagnosis", "ResidualAnalysis", "analyse_residuals", "auto_diagnose", "diagnose"]

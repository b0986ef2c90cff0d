"""Numerical optimisation the robots' controllers share: small dense linear and quadratic programs, each
solved by a solver its caller names (a fallback only when named, and said), with its certificate."""

from .programs import INFINITE, SOLVERS, Program, Solution, SolverError, solve

__all__ = ["INFINITE", "Program", "SOLVERS", "Solution", "SolverError", "solve"]

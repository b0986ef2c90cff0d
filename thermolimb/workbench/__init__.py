"""The workbench's judging side: fit on part of a log and validate by free run on the rest, error measures,
flags on fitted values, the comparison of models, a fleet of logs at once, and parameter drift across runs."""

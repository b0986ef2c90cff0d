"""Infrastructure every part of the suite shares: errors people can act on, files written whole, lazy imports,
JSON conversion, worker pools, progress bars and where the robot descriptions are.  Nothing here knows about
heat."""

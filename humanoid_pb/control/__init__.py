"""Control: the whole-body balance controller, the executor that moves between contact modes, and the
contact-mode planner of Jorgensen et al.'s Eq. 33."""

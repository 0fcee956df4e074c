"""The names of the study's steps, in the order a study runs and reports them."""

FINGER_STEPS = ("finger", "impulse", "contact", "design", "calibrate")
"""The steps of a study of the configured finger."""
PAPER_STEPS = ("table1", "steel_rod", "mesh", "damping_fits")
"""The steps that reproduce the paper (``[study] paper``), on the paper's finger."""
STEP_NAMES = FINGER_STEPS + PAPER_STEPS
LONGEST_FIRST = ("design", "contact", "damping_fits", "steel_rod", "mesh", "table1", "finger", "impulse", "calibrate")
"""Submission order on a cluster: the longest steps (measured) first."""

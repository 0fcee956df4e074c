"""Unit conversions. Everything inside ccedi is SI (m, kg, s, N, Pa); the paper
quotes finger lengths in inches, so conversions live here and nowhere else."""

INCH = 0.0254
"""One inch in metres (exact)."""


def inch_to_m(length_in):
    """Length in inches -> metres."""
    return length_in * INCH


def m_to_inch(length_m):
    """Length in metres -> inches."""
    return length_m / INCH

"""Unit conversions. Everything inside ccedi is SI (m, kg, s, N, Pa); the paper
quotes finger lengths in inches and drum speeds in rpm, so conversions live here and
nowhere else."""
import numpy as np

INCH = 0.0254
"""One inch in metres (exact)."""


def inch_to_m(length_in):
    """Convert a length in inches to metres.

    Parameters
    ----------
    length_in : float or numpy.ndarray
        Length [in].

    Returns
    -------
    float or numpy.ndarray
        ``length_in * 0.0254`` [m].
    """
    return length_in * INCH


def m_to_inch(length_m):
    """Convert a length in metres to inches.

    Parameters
    ----------
    length_m : float or numpy.ndarray
        Length [m].

    Returns
    -------
    float or numpy.ndarray
        ``length_m / 0.0254`` [in].
    """
    return length_m / INCH


RPM = 2.0 * np.pi / 60.0
"""One revolution per minute [rad/s]."""


def rpm_to_rad_s(speed_rpm):
    """Convert a rotation speed in revolutions per minute to rad/s.

    Parameters
    ----------
    speed_rpm : float or numpy.ndarray
        Speed [rpm].

    Returns
    -------
    float or numpy.ndarray
        ``speed_rpm * 2 pi / 60`` [rad/s].
    """
    return speed_rpm * RPM

"""Shared fixtures: the paper's 4.5-in SM-A finger and its analytic beam values."""
import pytest

from ccedi.fea.beam_theory import cantilever_frequencies, ellipse_section_properties, tip_stiffness_eb
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import sm_a
from ccedi.fea.units import inch_to_m

LENGTH_M = inch_to_m(4.5)


@pytest.fixture(scope="session")
def mesh_a():
    return sm_a(length_in=4.5)


@pytest.fixture(scope="session")
def euler_bernoulli():
    """Analytic tip stiffness [N/m] and first frequency [rad/s] of the 4.5-in finger."""
    area, inertia = ellipse_section_properties()
    return {"k_tip": tip_stiffness_eb(RUBBER.E, LENGTH_M, inertia),
            "omega1": cantilever_frequencies(RUBBER.E, RUBBER.rho, LENGTH_M, area, inertia)[0]}

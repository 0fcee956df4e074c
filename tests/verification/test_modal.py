"""Natural frequencies: convergence under mesh refinement towards Euler-Bernoulli."""
import numpy as np

from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import elliptical_cantilever
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.units import inch_to_m


def test_first_frequency_converges_under_refinement(euler_bernoulli):
    L = inch_to_m(4.5)
    omega1 = [natural_frequencies(cantilever(L, n, nz), n_modes=1)[0] for n, nz in ((3, 15), (5, 29), (7, 43))]
    # monotone from above (the one-point element with stiffness hourglass control is stiff
    # in bending), with shrinking increments, ending within 2 % of Euler-Bernoulli
    assert omega1[0] > omega1[1] > omega1[2]
    assert omega1[0] - omega1[1] > omega1[1] - omega1[2]
    assert abs(omega1[2] / euler_bernoulli["omega1"] - 1.0) < 0.02


def test_second_soft_bending_mode_ratio():
    """Second bending mode in the soft plane: omega2 / omega1 = (4.694/1.875)^2 = 6.27 for
    a slender beam; a 4.5-in finger with a 17 mm section is stubby, so shear and rotary
    inertia lower it (Timoshenko), but it stays within 10 %."""
    model = cantilever(inch_to_m(4.5), 5, 29)
    omega, modes = natural_frequencies(model, n_modes=4, return_modes=True)
    uy = modes[1::3]
    soft = [i for i in range(4) if np.abs(uy[:, i]).max() > np.abs(modes[0::3, i]).max()]
    ratio = omega[soft[1]] / omega[soft[0]]
    assert 0.9 * 6.27 < ratio < 6.27


def cantilever(L, n, nz):
    from ccedi.fea.model import cantilever_model
    return cantilever_model(elliptical_cantilever(L, n, nz), RUBBER)

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ccedi.errors import InputError
from ccedi.fea.material import RUBBER, NeoHookean, cauchy_stress, first_piola, strain_energy_density, von_mises

small = st.floats(-0.3, 0.3)


@settings(max_examples=40, deadline=None)
@given(st.lists(small, min_size=9, max_size=9))
def test_first_piola_is_derivative_of_strain_energy(entries):
    F = np.eye(3) + np.reshape(entries, (3, 3))
    if np.linalg.det(F) < 0.2:
        return
    mu, lam = RUBBER.mu, RUBBER.lam
    P = first_piola(F[None], mu, lam)[0]
    h = 1e-7
    dW = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            dF = np.zeros((3, 3))
            dF[i, j] = h
            dW[i, j] = (strain_energy_density((F + dF)[None], mu, lam)[0]
                        - strain_energy_density((F - dF)[None], mu, lam)[0]) / (2 * h)
    assert np.allclose(P, dW, rtol=1e-5, atol=1e-6 * RUBBER.E)


def test_small_strain_limit_is_hooke():
    rng = np.random.default_rng(1)
    eps = 1e-6 * rng.standard_normal((3, 3))
    eps = 0.5 * (eps + eps.T)
    mat = NeoHookean(E=6.1e6, nu=0.3, rho=1000.0)
    sigma = cauchy_stress((np.eye(3) + eps)[None], mat.mu, mat.lam)[0]
    hooke = mat.lam * np.trace(eps) * np.eye(3) + 2 * mat.mu * eps
    assert np.allclose(sigma, hooke, rtol=1e-4, atol=1e-4 * np.abs(hooke).max())


def test_uniaxial_von_mises_is_axial_stress():
    s = np.zeros((1, 3, 3))
    s[0, 0, 0] = 2.5e5
    assert von_mises(s)[0] == pytest.approx(2.5e5)


def test_wave_speed_of_rubber():
    # c = sqrt((lam + 2 mu) / rho); for nu = 0.49 the constrained modulus is ~ 17 E
    assert RUBBER.wave_speed == pytest.approx(np.sqrt(RUBBER.constrained_modulus / RUBBER.rho))
    assert 300.0 < RUBBER.wave_speed < 350.0


@pytest.mark.parametrize("kwargs, field", [
    ({"E": -1.0}, "E"), ({"E": float("nan")}, "E"), ({"rho": 0.0}, "rho"), ({"rho": float("nan")}, "rho"),
    ({"nu": 0.5}, "nu"), ({"nu": -1.0}, "nu"), ({"nu": 0.7}, "nu"), ({"nu": float("nan")}, "nu")])
def test_bad_material_values_are_named(kwargs, field):
    values = {"E": 6.1e6, "nu": 0.49, "rho": 1000.0, **kwargs}
    with pytest.raises(InputError, match=field):
        NeoHookean(**values)


def test_cauchy_stress_is_push_forward_of_first_piola():
    rng = np.random.default_rng(2)
    F = np.eye(3) + 0.2 * rng.standard_normal((20, 3, 3))
    F = F[np.linalg.det(F) > 0.3]
    P = first_piola(F, RUBBER.mu, RUBBER.lam)
    J = np.linalg.det(F)[:, None, None]
    assert np.allclose(cauchy_stress(F, RUBBER.mu, RUBBER.lam), P @ F.swapaxes(1, 2) / J, rtol=1e-10, atol=1e-6)

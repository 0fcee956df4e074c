"""Modal reduced model: exactness checks and the comparison with full FEA."""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from ccedi.fea.cases.studies import finger_impulse_model, impulse_model
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import elliptical_cantilever
from ccedi.fea.model import cantilever_model, face_node_weights
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.fea.solvers.static import tip_deflection
from ccedi.rom.ccedi import critical_alpha
from ccedi.rom.modal import ModalImpulseModel, ModalROM, fit_to_response, modal_rom, nrmse, tip_modal_rom


@pytest.fixture(scope="module")
def small_model():
    return cantilever_model(elliptical_cantilever(0.05, 2, 3), RUBBER)


def test_all_modes_reproduce_static_flexibility_exactly(small_model):
    """Modal completeness: with every mode kept, sum g_i / omega_i^2 is the static tip
    flexibility of the linear FE model."""
    n_free = 3 * (small_model.mesh.n_nodes - len(small_model.fixed_nodes))
    tip = small_model.mesh.node_sets["tip"]
    rom = modal_rom(small_model, n_free, load_nodes=tip, load_weights=face_node_weights(small_model.mesh, tip))
    assert rom.static_flexibility == pytest.approx(tip_deflection(small_model, 1.0, linear=True), rel=1e-9)


def test_rom_frequencies_are_the_fe_frequencies(small_model):
    tip = small_model.mesh.node_sets["tip"]
    rom = modal_rom(small_model, 5, load_nodes=tip, load_weights=face_node_weights(small_model.mesh, tip))
    assert np.allclose(rom.omega_rad_s, natural_frequencies(small_model, n_modes=5), rtol=1e-10)


@settings(max_examples=30, deadline=None)
@given(st.floats(0.01, 5.0), st.floats(5.0, 200.0))
def test_pulse_response_is_exact_for_any_damping(zeta, omega):
    rom = ModalROM(omega_rad_s=np.array([omega]), gain=np.array([2.0]), zeta_fitted=np.array([zeta]))
    T, F = 0.03, 1.5
    t = np.linspace(0.0, 0.2, 201)
    sol = solve_ivp(lambda s, q: [q[1], 2.0 * F * (s < T) - 2 * zeta * omega * q[1] - omega**2 * q[0]],
                    (0.0, 0.2), [0.0, 0.0], t_eval=t, rtol=1e-10, atol=1e-14, max_step=1e-3)
    assert np.allclose(rom.pulse_response(t, F, T), sol.y[0], atol=1e-6 * np.abs(sol.y[0]).max())


def test_state_space_matches_the_closed_form():
    import control
    rom = ModalROM(omega_rad_s=np.array([90.0, 520.0]), gain=np.array([110.0, 100.0]), alpha=180.0)
    t = np.linspace(0.0, 0.1, 2001)
    u = np.where(t < 0.01, 0.5, 0.0)
    y = np.asarray(control.forced_response(rom.state_space(), T=t, U=u).outputs)
    # forced_response interpolates the input linearly between samples, so its pulse ends
    # half a sample (25 us) earlier than the ideal rectangle
    assert np.allclose(y, rom.pulse_response(t, 0.5, 0.01 - 0.5 * (t[1] - t[0])), atol=1e-4 * np.abs(y).max())


@pytest.mark.slow
def test_rom_matches_full_fea_impulse():
    """Acceptance 1: 4.5-in finger, 0.1 N for 10 ms (small amplitude), alpha = 20 1/s:
    NRMSE < 2 % with 3 modes, fitted frequencies within 1 % of the FE model's for the modes
    that carry at least 1 % of the static tip flexibility. The same acceptance at alpha =
    180 1/s (where the third mode carries 0.4 % and, heavily damped, is not resolved by the
    response: its fit moves 1.5 %) is checked on the ``rom-check`` command's output, which
    runs that case (tests/unit/rom/test_contact_rom.py::test_rom_check_cli_writes_the_case_keys)."""
    alpha, force, duration = 20.0, 0.1, 0.01
    h = finger_impulse_model(force_N=force, duration_s=duration).run(alpha, 0.2, 400).history
    rom = tip_modal_rom(impulse_model(alpha=alpha, force_N=force), n_modes=3)
    assert nrmse(rom.pulse_response(h.time_s, force, duration), h.tip_uy_m) < 0.02
    fit = fit_to_response(rom, h.time_s.values, h.tip_uy_m.values, force_N=force, duration_s=duration)
    assert fit.nrmse_after < 0.02 and fit.nrmse_after <= fit.nrmse_before
    share = (rom.gain / rom.omega_rad_s**2) / rom.static_flexibility
    seen = share >= 0.01
    assert seen.sum() >= 2
    assert np.allclose(fit.rom.omega_rad_s[seen], rom.omega_rad_s[seen], rtol=0.01)


def test_ccedi_runs_on_the_surrogate():
    """The CCEDI bisection takes the ROM through the same impulse-model interface."""
    model = impulse_model(alpha=0.0)
    rom = tip_modal_rom(model, n_modes=6)
    omega1 = rom.omega_rad_s[0]
    crit = critical_alpha(ModalImpulseModel(rom, 1.0, 0.01), 2.0 * omega1, 0.01 + 12.0 / omega1, rtol=0.005)
    assert crit.alpha_cr_per_s == pytest.approx(2.0 * omega1, rel=0.05)

"""The compiled chain step loop against its plain Python / numpy reference."""
from dataclasses import replace

import numpy as np
import pytest

from ccedi.fea.contact.drum import DrumSetup
from ccedi.rom.chain_dynamics import ChainOutputs, ChainState, ContactPoints, DrumFrame, chain_run
from ccedi.rom.contact_rom import ReducedContactModel

COARSE = DrumSetup(finger_section_elements=3, finger_elements_along=26)
"""The coarse 8-in contact case of tests/unit/rom/test_contact_rom.py."""

T_CONTACT_S = 0.302
"""Drum time, from the calibrated start, shortly before the finger meets the object [s]
(contact in 5 of the 8 outputs of the 400-step runs below)."""


def _run(model, alpha, damping, n_steps, n_outputs, backend):
    """Run the chain of ``model`` for n_steps steps from rest in the drum frame."""
    s, ch = model.setup, model.chain
    n = len(ch.station_z_m)
    state = ChainState(np.column_stack([s.drum_radius_m + ch.station_z_m, np.zeros(n)]), np.zeros(n),
                       np.zeros((n, 2)), np.zeros(n))
    t_out = np.linspace(0.0, n_steps * model.dt_s, n_outputs + 1)[1:]
    out = ChainOutputs(t_out, np.zeros((n_outputs, n, 2)), np.zeros((n_outputs, n)), np.zeros((n_outputs, 6)))
    obj = s.object_surface
    points = ContactPoints(model.pt_seg, model.pt_xi, model.pt_h, model.pt_k, float(obj.damping_ratio), float(obj.mu),
                           obj.params()[1][:6])
    drum = DrumFrame(s.omega_rad_s, s.theta0_rad, float(alpha), damping == "relative")
    status, steps = chain_run(state, model._chain_group(), drum, points=points, dt=model.dt_s, outputs=out,
                              backend=backend)
    return status, steps, state, out


@pytest.mark.parametrize("contact, damping, zeta", [("stations", "global", 0.0), ("face", "relative", 0.0),
                                                    ("stations", "global", 0.2)])
def test_compiled_chain_run_matches_the_numpy_reference(contact, damping, zeta):
    """Coarse chain started just before contact, 400 steps with penalty contact and
    friction active. fastmath (reassociation, fused multiply-adds) changes the last bits
    of every step; over 400 steps they stay near 1e-12 of the values, so the states and
    the contact record must agree to rtol 1e-9 (far above round-off, far below any
    modelling change: one step's contact force changes it by > 1e-3). With contact damping
    (zeta 0.2) as well."""
    setup = replace(COARSE, theta0_rad=COARSE.theta0_rad + COARSE.omega_rad_s * T_CONTACT_S,
                    contact_damping_ratio=zeta)
    model = ReducedContactModel(setup, n_segments=13, contact=contact)
    ref = _run(model, 180.0, damping, 400, 8, "numpy")
    got = _run(model, 180.0, damping, 400, 8, "numba")
    assert ref[0] == got[0] == 0 and ref[1] == got[1] >= 400
    C_ref, C_got = ref[3].C_out, got[3].C_out
    assert (C_ref[:, 2] > 0).sum() >= 4                     # contact in most outputs
    assert np.array_equal(C_ref[:, 2], C_got[:, 2])         # same active point counts
    for a, b in zip(ref[2], got[2]):
        assert np.allclose(b, a, rtol=1e-9, atol=1e-9 * np.abs(a).max())
    assert np.allclose(C_got, C_ref, rtol=1e-9, atol=1e-9 * np.abs(C_ref).max(axis=0))
    assert np.allclose(got[3].P_out, ref[3].P_out, rtol=1e-9, atol=1e-12)


def test_output_force_is_the_mean_over_its_interval():
    """The force on the object at an output is the mean of the steps' forces since the
    previous output (anti-aliased): 400 steps recorded at every step, and at every 50th,
    give the same states and, at the coarse outputs, the mean of the 50 step forces."""
    setup = replace(COARSE, theta0_rad=COARSE.theta0_rad + COARSE.omega_rad_s * T_CONTACT_S)
    model = ReducedContactModel(setup, n_segments=13)
    fine = _run(model, 180.0, "global", 400, 400, "numba")
    coarse = _run(model, 180.0, "global", 400, 8, "numba")
    assert fine[1] == coarse[1] == 400
    f_fine, f_coarse = fine[3].C_out[:, :2], coarse[3].C_out[:, :2]
    assert np.abs(f_fine).max() > 0.0
    assert np.allclose(f_coarse, f_fine.reshape(8, 50, 2).mean(axis=1), rtol=1e-12, atol=1e-12 * np.abs(f_fine).max())
    assert np.allclose(coarse[3].P_out, fine[3].P_out[49::50], rtol=1e-12, atol=1e-15)

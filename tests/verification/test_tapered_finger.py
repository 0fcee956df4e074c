"""The generated finger tapered: its section similar to the root's and scaled linearly
along the length by the taper ratio lambda. Checked against exact geometry (the tip
section, the volume (1 + lambda + lambda^2) / 3 of the prism's), against the tapered
Euler-Bernoulli cantilever (tip stiffness exactly lambda times the prism's, the first
frequency from a converged beam solve), and carried to the contact ROM through the drum
set-up (its chain has the FE finger's first frequency, its contact faces follow the
taper, and a taper on a given mesh is refused)."""
import numpy as np
import pytest
from scipy.integrate import quad

from ccedi.errors import InputError
from ccedi.fea.cases.beam_theory import (
    cantilever_frequencies,
    ellipse_section_properties,
    tapered_cantilever_frequencies,
    tapered_tip_stiffness_eb,
    tip_stiffness_eb,
)
from ccedi.fea.contact.drum import DrumSetup, FullContactModel, finger_mesh
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXES, elliptical_cantilever, sm_a
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.fea.solvers.static import tip_deflection
from ccedi.rom.contact_rom import reduce_contact_model
from ccedi.rom.superelement import chain_frequencies
from ccedi.units import INCH

LENGTH_M = 4.5 * INCH


def _finger(taper_ratio):
    return elliptical_cantilever(LENGTH_M, 5, 30, taper_ratio=taper_ratio)


@pytest.mark.parametrize("taper_ratio", [0.4, 0.7, 1.5])
def test_tapered_mesh_has_the_scaled_tip_section_and_the_frustum_volume(taper_ratio):
    """The hex mesh's volume integrates exactly (trilinear elements, sections scaled
    linearly): the prism's times (1 + lambda + lambda^2) / 3 to round-off."""
    a, b = SEMI_AXES
    mesh = _finger(taper_ratio)
    tip = mesh.nodes[mesh.node_sets["tip"]]
    np.testing.assert_allclose(np.abs(tip[:, :2]).max(axis=0), [taper_ratio * a, taper_ratio * b], rtol=1e-12)
    mass = cantilever_model(mesh, RUBBER).mass.sum()
    prism = cantilever_model(_finger(1.0), RUBBER).mass.sum()
    assert mass / prism == pytest.approx((1 + taper_ratio + taper_ratio**2) / 3, rel=1e-10)


def test_the_beam_references_hold_for_the_prism_and_the_integral():
    """The tapered beam's references: at lambda = 1 the prism's closed forms; the tip
    stiffness against the deflection integral; the frequency converged in the elements."""
    area, inertia = ellipse_section_properties()
    np.testing.assert_allclose(
        tapered_cantilever_frequencies(RUBBER.E, RUBBER.rho, LENGTH_M, area=area, second_moment=inertia,
                                       taper_ratio=1.0, n_modes=3),
        cantilever_frequencies(RUBBER.E, RUBBER.rho, LENGTH_M, area=area, second_moment=inertia, n_modes=3),
        rtol=1e-6)
    lam = 0.4
    flexibility = quad(lambda z: (LENGTH_M - z) ** 2 / (1 - (1 - lam) * z / LENGTH_M) ** 4, 0, LENGTH_M)[0]
    assert tapered_tip_stiffness_eb(RUBBER.E, LENGTH_M, inertia, taper_ratio=lam) == pytest.approx(
        RUBBER.E * inertia / flexibility, rel=1e-9)
    coarse, fine = (tapered_cantilever_frequencies(RUBBER.E, RUBBER.rho, LENGTH_M, area=area, second_moment=inertia,
                                                   taper_ratio=lam, n_elements=n)[0] for n in (25, 100))
    assert coarse == pytest.approx(fine, rel=1e-6)
    with pytest.raises(InputError, match="taper_ratio"):
        tapered_cantilever_frequencies(RUBBER.E, RUBBER.rho, LENGTH_M, area=area, second_moment=inertia,
                                       taper_ratio=0.0)


@pytest.mark.parametrize("taper_ratio", [0.4, 0.6])
def test_fe_tapered_finger_against_the_tapered_euler_bernoulli_beam(taper_ratio):
    """Tip stiffness (linear, 1 N) over the prism's against lambda (measured 0.390 at
    0.4, 0.590 at 0.6: the tip's shear and the load's spread on a smaller face), and
    the first frequency against the tapered beam's (FE +0.1 %, +0.5 %)."""
    area, inertia = ellipse_section_properties()
    model = cantilever_model(_finger(taper_ratio), RUBBER)
    prism = cantilever_model(_finger(1.0), RUBBER)
    ratio = tip_deflection(prism, 1.0, linear=True) / tip_deflection(model, 1.0, linear=True)
    exact = tapered_tip_stiffness_eb(RUBBER.E, LENGTH_M, inertia, taper_ratio=taper_ratio) / tip_stiffness_eb(
        RUBBER.E, LENGTH_M, inertia)
    assert ratio == pytest.approx(exact, rel=0.04)
    omega_beam = tapered_cantilever_frequencies(RUBBER.E, RUBBER.rho, LENGTH_M, area=area, second_moment=inertia,
                                                taper_ratio=taper_ratio)[0]
    assert natural_frequencies(model, n_modes=1)[0] == pytest.approx(omega_beam, rel=0.02)


def test_the_drum_set_up_carries_the_taper_to_the_fe_finger_and_the_rom():
    """The set-up's finger is SM-A tapered; the contact ROM reduced from it has the FE
    finger's first bending frequency (within 3 %, as on the gmsh tapered finger) and
    contact faces at the tapered half thickness of each station."""
    setup = DrumSetup(finger_length_m=LENGTH_M, finger_taper_ratio=0.5)
    mesh = finger_mesh(setup)
    prism = sm_a(length_m=LENGTH_M)
    assert mesh.nodes.shape == prism.nodes.shape
    np.testing.assert_allclose(mesh.nodes[:, 2], prism.nodes[:, 2], rtol=0, atol=1e-15)
    assert setup.finger_thickness_m == pytest.approx(2 * SEMI_AXES[1])
    rom = reduce_contact_model(FullContactModel(setup, object_stress=False))
    omega_fe = natural_frequencies(cantilever_model(mesh, RUBBER), n_modes=1)[0]
    assert chain_frequencies(rom.chain, 1)[0] == pytest.approx(omega_fe, rel=0.03)
    b = SEMI_AXES[1] * (1 - 0.5 * rom.chain.station_z_m / LENGTH_M)
    np.testing.assert_allclose(rom.chain.face_offsets_m, np.column_stack([b, b]), rtol=0, atol=0.3e-3)


def test_a_bad_taper_is_refused_in_one_line():
    for bad in (0.1, 2.5, float("nan")):
        with pytest.raises(InputError, match="taper_ratio") as err:
            elliptical_cantilever(LENGTH_M, 2, 4, taper_ratio=bad)
        assert "\n" not in str(err.value)
    with pytest.raises(InputError, match="finger_taper_ratio"):
        DrumSetup(finger_taper_ratio=0.05)
    with pytest.raises(InputError, match="given mesh.*generated finger only"):
        DrumSetup(finger=_finger(1.0), finger_taper_ratio=0.5)

"""An imported finger that is not a prism (a Gmsh file: tapered elliptical section with a
transverse hole, 10-node tetrahedra) through ``table1``, ``impulse`` and ``identify``."""
import json

import numpy as np
import pytest
from scipy.integrate import quad

from ccedi.fea.material import RUBBER
from ccedi.fea.mesh.gmsh_fingers import TAPERED_ROOT_SEMI_AXES, TAPERED_TIP_SEMI_AXES, write_tapered_finger
from ccedi.fea.mesh.readers import read_finger_mesh
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.fea.solvers.static import tip_deflection
from ccedi.study.cli import main
from ccedi.units import inch_to_m

SIZE_M = 6e-3          # the coarsest of the refinement sizes: a few seconds per solve


@pytest.fixture(scope="module")
def finger(tmp_path_factory):
    """(TOML path, mesh path, CAD volume [m^3]) of the tapered finger with a hole."""
    d = tmp_path_factory.mktemp("finger")
    volume = write_tapered_finger(d / "finger.msh", SIZE_M)
    toml = d / "finger.toml"
    toml.write_text('[finger]\nmesh = "finger.msh"\nclamp = "clamp"\ntip = "tip"\n')
    return toml, d / "finger.msh", volume


def _tapered_beam_stiffness(E, length_m):
    """Euler-Bernoulli tip stiffness F / delta = 1 / int (L - z)^2 / (E I(z)) dz [N/m] of the
    finger without its hole, semi-axes linear in z, I = pi a b^3 / 4."""
    def semi(z, i):
        return TAPERED_ROOT_SEMI_AXES[i] + (TAPERED_TIP_SEMI_AXES[i] - TAPERED_ROOT_SEMI_AXES[i]) * z / length_m

    def inertia(z):
        return np.pi * semi(z, 0) * semi(z, 1) ** 3 / 4.0
    return 1.0 / quad(lambda z: (length_m - z) ** 2 / (E * inertia(z)), 0.0, length_m)[0]


def test_table1_row_of_an_imported_finger(finger, tmp_path):
    toml, msh, volume = finger
    path = tmp_path / "t1.json"
    assert main(["table1", "--no-stiffness", "--no-detailed-model", "--config", str(toml), "--json", str(path)]) == 0
    row = json.loads(path.read_text())["finger"]
    mesh = read_finger_mesh(msh, clamp="clamp", tip="tip")
    assert (row["element_type"], row["nodes"], row["elements"]) == ("tet10", mesh.n_nodes, mesh.n_elements)
    assert row["volume_cm3"] == pytest.approx(1e6 * volume, rel=1e-3)        # the CAD volume, hole included
    assert row["steps_to_0_2_s"] == pytest.approx(0.2 / (1e-6 * row["dt_us"]), abs=1)
    omega1 = natural_frequencies(cantilever_model(mesh, RUBBER), n_modes=1)[0]
    assert row["omega1_rad_s"] == pytest.approx(omega1, rel=1e-9)


def test_imported_finger_is_a_little_softer_than_its_tapered_beam(finger):
    """Shear and the hole can only soften the Euler-Bernoulli beam of the same taper."""
    _, msh, _ = finger
    model = cantilever_model(read_finger_mesh(msh, clamp="clamp", tip="tip"), RUBBER)
    k = 1.0 / tip_deflection(model, 1.0, linear=True)
    k_beam = _tapered_beam_stiffness(RUBBER.E, inch_to_m(4.5))
    assert 0.85 * k_beam < k < k_beam


def test_alpha_cr_on_the_modal_rom_of_an_imported_finger(finger, tmp_path):
    toml, msh, _ = finger
    path = tmp_path / "acr.json"
    assert main(["identify", "--alpha-cr", "--rom", "6", "--rtol", "0.02", "--config", str(toml),
                 "--json", str(path)]) == 0
    out = json.loads(path.read_text())
    assert out["finger"]["mesh_file"] == str(msh.resolve()) and out["finger"]["element_type"] == "tet10"
    model = cantilever_model(read_finger_mesh(msh, clamp="clamp", tip="tip"), RUBBER)
    omega1 = natural_frequencies(model, n_modes=1)[0]
    assert out["omega1_rad_s"] == pytest.approx(omega1, rel=1e-9)
    # a nearly critically damped first mode: alpha_cr = 2 zeta_cr omega_1, zeta_cr just below 1
    assert 0.9 * 2.0 * omega1 < out["alpha_cr_per_s"] < 2.0 * omega1


def test_length_flag_beside_a_mesh_is_refused(finger, capsys):
    toml, _, _ = finger
    assert main(["impulse", "--length-in", "3", "--config", str(toml), "--t-end-s", "0.001"]) == 1
    err = capsys.readouterr().err
    assert "--length-in" in err and "mesh" in err and len(err.strip().splitlines()) == 1


@pytest.mark.slow
def test_impulse_on_an_imported_finger(finger, tmp_path):
    toml, _, _ = finger
    out = tmp_path / "imp"
    assert main(["impulse", "--alpha", "180", "--t-end-s", "0.01", "--config", str(toml), "--out", str(out)]) == 0
    summary = json.loads((out / "impulse_summary.json").read_text())
    assert summary["finger"]["element_type"] == "tet10"
    healthy, slivers = [[w for w in summary["warnings"] if ("the step is set by" in w) == s] for s in (False, True)]
    assert healthy == []                                             # energy balance, strains: healthy
    assert all("remesh" in w for w in slivers)                       # a sliver where the hole meets the surface
    run = summary["runs"][0]
    assert run["steps"] == pytest.approx(0.01 / run["dt_initial_s"], rel=0.05)


@pytest.mark.skipif(__import__("shutil").which("ccx") is None, reason="CalculiX (ccx) not installed: "
                    "apt-get install calculix-ccx")
def test_tet10_is_calculix_c3d10_where_the_volumetric_treatment_does_not_matter(finger):
    """At nu = 0 (no lam term, so mean dilatation changes nothing) ccedi's 10-node
    tetrahedron and CalculiX's C3D10 are the same element: the same tip stiffness on the
    same imported mesh. At nu = 0.49 ccedi's (mean dilatation, locking-free) is the softer."""
    from ccedi.fea.io.calculix import run_calculix
    from ccedi.fea.material import NeoHookean
    from ccedi.fea.model import face_node_weights

    _, msh, _ = finger
    mesh = read_finger_mesh(msh, clamp="clamp", tip="tip")
    weights = face_node_weights(mesh, mesh.node_sets["tip"])
    for nu, (lo, hi) in ((0.0, (1.0 - 1e-6, 1.0 + 1e-6)), (0.49, (0.95, 1.0))):
        material = NeoHookean(E=6.1e6, nu=nu, rho=1000.0)
        k = 1.0 / tip_deflection(cantilever_model(mesh, material), 1.0, linear=True)
        peer = run_calculix(mesh, material, weights=weights)
        assert lo < k / peer.stiffness_N_per_m < hi

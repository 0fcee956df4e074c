"""LS-DYNA deck round trip: what we write, our parser reads back unchanged."""
import numpy as np
import pytest

from ccedi.errors import InputError
from ccedi.fea.drum import DrumSetup, finger_on_drum
from ccedi.fea.lsdyna import read_keyword, write_keyword
from ccedi.fea.studies import impulse_model


def test_sm_a_impulse_deck_round_trip(tmp_path):
    model = impulse_model(length_in=4.5, alpha=180.0, force_N=1.0, duration_s=0.01)
    path = write_keyword(model, tmp_path / "sm_a.k", t_end_s=0.2)
    text = path.read_text()
    for card in ("*NODE", "*ELEMENT_SOLID", "*MAT_ELASTIC", "*DAMPING_GLOBAL", "*CONTROL_TIMESTEP",
                 "*BOUNDARY_SPC_SET", "*LOAD_NODE_SET", "*END"):
        assert card in text
    deck = read_keyword(path)
    assert deck.nodes.shape == (1080, 3) and deck.hexes.shape == (725, 8)
    np.testing.assert_allclose(deck.nodes, model.mesh.nodes, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(deck.hexes, model.mesh.hexes)
    m = model.material
    assert deck.material == {"rho": m.rho, "E": m.E, "nu": m.nu}
    assert deck.alpha_per_s == 180.0 and deck.tssfac == 0.9 and deck.t_end_s == 0.2
    assert len(deck.spc_sets) == 1
    np.testing.assert_array_equal(np.sort(deck.node_sets[deck.spc_sets[0]]), np.sort(model.fixed_nodes))
    pulse = model.pulses[0]
    loaded = np.concatenate([ld["nodes"] for ld in deck.loads])
    np.testing.assert_array_equal(np.sort(loaded), np.sort(pulse.nodes))
    total = np.zeros(3)
    for ld in deck.loads:
        total[ld["dof"]] += ld["force_N"] * len(ld["nodes"])
        assert (ld["t_start_s"], ld["t_end_s"]) == (0.0, 0.01)
    np.testing.assert_allclose(total, pulse.force_N, rtol=1e-12)
    for ld in deck.loads:   # each node carries its own share of the pulse
        w = dict(zip(pulse.nodes.tolist(), pulse.weights))
        np.testing.assert_allclose([w[n] for n in ld["nodes"].tolist()], ld["force_N"], rtol=1e-12)


def test_contact_deck_has_contact_and_rotation(tmp_path):
    model, _ = finger_on_drum(DrumSetup(), alpha=7.5)
    deck = read_keyword(write_keyword(model, tmp_path / "drum.k", t_end_s=1.5))
    text = (tmp_path / "drum.k").read_text()
    assert "*CONTACT_AUTOMATIC_NODES_TO_SURFACE" in text and "*BOUNDARY_PRESCRIBED_MOTION_SET" in text
    assert deck.contact["static_friction"] == 0.6
    np.testing.assert_array_equal(np.sort(deck.contact["nodes"]), np.sort(model.contact.nodes))
    np.testing.assert_allclose(deck.nodes, model.mesh.nodes, atol=1e-12)


def test_relative_damping_is_refused(tmp_path):
    model, _ = finger_on_drum(DrumSetup(), alpha=7.5, damping="relative")
    with pytest.raises(InputError, match="relative"):
        write_keyword(model, tmp_path / "x.k", t_end_s=1.0)

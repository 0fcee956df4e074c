"""One model interface (ccedi.models): the same study code drives the full and the
reduced models: CCEDI's alpha_cr search on either impulse model, the design's surrogate
runs from a model factory (the conformance of each model: tests/unit/core/test_model_conformance.py)."""
import pandas as pd
import pytest

from ccedi.design import surrogate
from ccedi.design.surrogate import cached_rom_runs, rom_factory, run_rom
from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.fea.contact.drum import DrumSetup
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXES, elliptical_cantilever
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.models import (
    ImpulseModel,
)
from ccedi.rom.ccedi import critical_alpha
from ccedi.rom.modal import ModalImpulseModel, reduce_impulse_model
from ccedi.units import inch_to_m

COARSE = DrumSetup(finger_section_elements=3, finger_elements_along=26)
"""The 8-in contact case on a 3 x 3 x 26 finger mesh (as tests/unit/rom/test_contact_rom.py)."""



@pytest.fixture(scope="module")
def finger_3in():
    """A coarse 3-in finger (3 x 3 x 10) as a full FE impulse model and its modal ROM."""
    mesh = elliptical_cantilever(inch_to_m(3.0), 3, 10, a=SEMI_AXES[0], b=SEMI_AXES[1])
    full = finger_impulse_model(mesh=mesh)
    omega1 = float(natural_frequencies(cantilever_model(mesh, RUBBER), n_modes=1)[0])
    return full, reduce_impulse_model(full, n_modes=6), omega1


def alpha_cr_of(model: ImpulseModel, omega1):
    """The one CCEDI alpha_cr search, whatever the model."""
    return critical_alpha(model, 2.0 * omega1, model.duration_s + 12.0 / omega1, rtol=0.02, n_outputs=300)


def test_same_alpha_cr_search_on_full_and_reduced_impulse_models(finger_3in):
    full, reduced, omega1 = finger_3in
    assert isinstance(full, ImpulseModel) and isinstance(reduced, ImpulseModel)
    assert isinstance(reduced, ModalImpulseModel) and (reduced.force_N, reduced.duration_s) == (1.0, 0.01)
    crit = {m.name: alpha_cr_of(m, omega1) for m in (full, reduced)}
    assert crit["modal-6"].alpha_cr_per_s == pytest.approx(crit["fea"].alpha_cr_per_s, rel=0.04)
    assert crit["fea"].alpha_cr_per_s == pytest.approx(2.0 * omega1, rel=0.06)


def test_design_builds_its_surrogate_runs_from_the_factory(tmp_path, monkeypatch):
    calls = []

    def factory(setup):
        calls.append(setup.finger_length_m)
        return rom_factory(setup)

    L = inch_to_m(4.0)
    points = [(50.0, L), (200.0, L)]
    frame = run_rom(DrumSetup(), points, model_factory=factory)
    assert calls == [L]                                     # one build per length, by the factory
    default = run_rom(DrumSetup(), points)
    pd.testing.assert_frame_equal(frame.drop(columns="wall_time_s"), default.drop(columns="wall_time_s"))
    path = tmp_path / "grid.csv"
    again, cached = cached_rom_runs(DrumSetup(), points, path, model_factory=factory)
    assert not cached and len(calls) == 2
    assert "factory" in (tmp_path / "grid.json").read_text()
    _, cached = cached_rom_runs(DrumSetup(), points, path)  # another model: the cache does not apply
    assert not cached
    _, cached = cached_rom_runs(DrumSetup(), points, path)
    assert cached
    monkeypatch.setattr(surrogate, "model_source_sha256", lambda: "the FE or ROM code changed")
    _, cached = cached_rom_runs(DrumSetup(), points, path)  # the models' code changed: run again
    assert not cached

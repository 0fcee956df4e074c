"""One model interface (ccedi.models): the same study code drives the full and the
reduced models, impulse (CCEDI's alpha_cr search) and contact (the contact summary)."""
import numpy as np
import pandas as pd
import pytest

from ccedi.design.surrogate import cached_rom_runs, rom_factory, run_rom
from ccedi.errors import InputError
from ccedi.fea.cases.steel_rod import steel_rod_impulse_model
from ccedi.fea.cases.studies import FullImpulseModel, finger_impulse_model
from ccedi.fea.contact.drum import DrumSetup, FullContactModel
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import SEMI_AXES, elliptical_cantilever
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers.modal import natural_frequencies
from ccedi.models import (
    CONTACT_CORE_COLUMNS,
    CONTACT_CORE_SUMMARY,
    IMPULSE_CORE_COLUMNS,
    IMPULSE_CORE_SUMMARY,
    ContactModel,
    ContactResponse,
    ImpulseModel,
    ImpulseResponse,
    contact_timing,
    validate_run_args,
)
from ccedi.rom.ccedi import critical_alpha
from ccedi.rom.contact_rom import ReducedContactModel
from ccedi.rom.modal import ModalImpulseModel, reduce_impulse_model
from ccedi.units import inch_to_m

COARSE = DrumSetup(finger_section_elements=3, finger_elements_along=26)
"""The 8-in contact case on a 3 x 3 x 26 finger mesh (as tests/test_contact_rom.py)."""

SHORT = {"t_end_s": 0.7, "n_outputs": 70}
"""A contact run that covers first contact (alpha = 180 1/s touches at ~0.33 s)."""


@pytest.fixture(scope="module")
def finger_3in():
    """A coarse 3-in finger (3 x 3 x 10) as a full FE impulse model and its modal ROM."""
    a, b = SEMI_AXES
    mesh = elliptical_cantilever(inch_to_m(3.0), 3, 10, a=a, b=b)
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


def test_impulse_responses_hold_the_core(finger_3in):
    full, reduced, _ = finger_3in
    core = [c.name for c in IMPULSE_CORE_COLUMNS]
    responses = [m.run(100.0, 0.02, 20) for m in (full, reduced)]
    for r in responses:
        assert isinstance(r, ImpulseResponse)
        assert set(core) <= set(r.history.columns)
        assert set(c.name for c in IMPULSE_CORE_SUMMARY) <= set(r.summary)
        assert r.summary["alpha_per_s"] == 100.0
    assert np.array_equal(responses[0].history.time_s, responses[1].history.time_s)
    assert list(responses[1].history.columns) == core                   # the ROM: the core only
    rod = steel_rod_impulse_model(n_elements=10)
    assert isinstance(rod, FullImpulseModel) and rod.run(1.0, 0.01, 5).summary["model"] == "fea-rod"


def contact_figures(model: ContactModel, alpha=180.0):
    """The one contact-summary code, whatever the model: the core, the timing recomputed
    from the core history, and the response itself."""
    response = model.run(alpha, damping="global", **SHORT)
    history, summary = response.core()
    return history, summary, contact_timing(history)


@pytest.fixture(scope="module")
def contact_responses():
    models = [FullContactModel(COARSE, object_stress=False), ReducedContactModel(COARSE, n_segments=13),
              ReducedContactModel(COARSE, n_segments=13, contact="face")]
    return {m.name + ("-face" if getattr(m, "contact", "") == "face" else ""): contact_figures(m) for m in models}


def test_same_contact_summary_on_full_and_reduced_models(contact_responses):
    for name, (history, summary, timing) in contact_responses.items():
        assert summary["model"] in name
        assert {k: summary[k] for k in timing} == timing, name
        assert summary["contact_start_s"] is not None, name
        assert len(history) == SHORT["n_outputs"]
    fea = contact_responses["fea"][1]
    for name in ("rom-corotational", "rom-corotational-face"):
        rom = contact_responses[name][1]
        assert rom["contact_start_s"] == pytest.approx(fea["contact_start_s"], abs=0.03), name


def test_contact_responses_declare_the_same_core_columns(contact_responses):
    names = [c.name for c in CONTACT_CORE_COLUMNS]
    assert list(ContactResponse.core_columns) == names
    assert list(ContactResponse.core_summary) == [c.name for c in CONTACT_CORE_SUMMARY]
    for history, summary, _ in contact_responses.values():
        assert list(history.columns) == names
        counts = history.contact_nodes.to_numpy()               # FE: float column, ROM: int; both counts
        assert np.array_equal(counts, np.round(counts)) and (counts >= 0).all()
    with pytest.raises(InputError, match="contact_nodes"):
        ContactResponse(history=pd.DataFrame({c: [0.0] for c in names if c != "contact_nodes"}),
                        summary={c.name: None for c in CONTACT_CORE_SUMMARY})


@pytest.mark.parametrize("kwargs, match", [({"alpha": -1.0}, "alpha"), ({"damping": "local"}, "damping"),
                                           ({"t_end_s": 0.0}, "t_end_s"), ({"n_outputs": 2.5}, "n_outputs")])
def test_every_model_checks_its_run_arguments_alike(kwargs, match, finger_3in):
    args = {"alpha": 10.0, "damping": "global", "t_end_s": 0.01, "n_outputs": 2, **kwargs}
    with pytest.raises(InputError, match=match):
        validate_run_args(args["alpha"], args["t_end_s"], args["n_outputs"], damping=args["damping"])
    models = [FullContactModel(COARSE, object_stress=False), ReducedContactModel(COARSE, n_segments=5)]
    for m in models:
        with pytest.raises(InputError, match=match):
            m.run(**args)
    if "damping" not in kwargs:
        args.pop("damping")
        for m in finger_3in[:2]:
            with pytest.raises(InputError, match=match):
                m.run(**args)


def test_design_builds_its_surrogate_runs_from_the_factory(tmp_path):
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

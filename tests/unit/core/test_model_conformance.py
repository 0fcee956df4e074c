"""One conformance test for every model of a kind (ccedi.models): the full FE model and the
reduced model its reductor makes pass the same checks, so that a study, the design and the
checks can take either.

Impulse: the coarse 3-in FE finger and its 6-mode modal ROM
(:func:`ccedi.rom.modal.reduce_impulse_model`), and the steel rod (full only: the modal
reductor needs solid elements). Contact: the
coarse 8-in finger on the drum and the chain ROMs its reductor makes
(:func:`ccedi.rom.contact_rom.reduce_contact_model`, stations and face contact).
"""
import inspect

import numpy as np
import pandas as pd
import pytest

from ccedi.design.optimise import Design
from ccedi.design.outputs import OUTPUTS
from ccedi.design.recheck import model_run
from ccedi.errors import InputError
from ccedi.fea.cases.steel_rod import steel_rod_impulse_model
from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.fea.contact.drum import DrumSetup, FullContactModel
from ccedi.fea.mesh import SEMI_AXES, elliptical_cantilever
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
    pulse_times,
)
from ccedi.rom.contact_rom import ReducedContactModel, reduce_contact_model
from ccedi.rom.modal import ModalImpulseModel, reduce_impulse_model
from ccedi.units import inch_to_m

COARSE = DrumSetup(finger_section_elements=3, finger_elements_along=26)
"""The 8-in contact case on a 3 x 3 x 26 finger mesh."""
CONTACT_RUN = {"t_end_s": 0.6, "n_outputs": 60}
"""A contact run past first contact (alpha = 180 1/s touches at ~0.33 s)."""
IMPULSE_RUN = {"t_end_s": 0.03, "n_outputs": 30}
"""An impulse run of the finger: its 10 ms pulse and as long after it."""


def _names(columns):
    return [c.name for c in columns]


@pytest.fixture(scope="module")
def impulse_models():
    """{label: model}: two full impulse models and the finger's reduced model (the modal
    reductor needs solid elements: the steel rod, a structure of rods, is refused)."""
    finger = finger_impulse_model(mesh=elliptical_cantilever(inch_to_m(3.0), 3, 10, a=SEMI_AXES[0], b=SEMI_AXES[1]))
    rod = steel_rod_impulse_model(n_elements=10)
    with pytest.raises(InputError, match="solid elements"):
        reduce_impulse_model(rod)
    return {"finger-fea": finger, "finger-modal": reduce_impulse_model(finger, n_modes=6), "rod-fea": rod}


@pytest.fixture(scope="module")
def contact_models():
    """{label: model}: the full contact model and the reduced ones its reductor makes."""
    full = FullContactModel(COARSE, object_stress=False)
    return {"fea": full, "rom-stations": reduce_contact_model(full, n_segments=13),
            "rom-face": reduce_contact_model(full, n_segments=13, contact="face"),
            "rom-linear": reduce_contact_model(full, n_segments=13, nonlinear=False)}


@pytest.fixture(scope="module")
def contact_responses(contact_models):
    """{label: (response at alpha 180, the same run again)}: two runs each, for determinism."""
    return {k: [m.run(180.0, damping="global", **CONTACT_RUN) for _ in range(2)] for k, m in contact_models.items()}


def _same_signature(method, protocol_method):
    """The run method's parameter names and defaults are the protocol's."""
    ours = list(inspect.signature(method).parameters.values())
    theirs = list(inspect.signature(protocol_method).parameters.values())[1:]          # without self
    assert [(p.name, p.default) for p in ours] == [(p.name, p.default) for p in theirs]


@pytest.mark.parametrize("label", ["finger-fea", "finger-modal", "rod-fea"])
def test_impulse_model_conformance(impulse_models, label):
    model = impulse_models[label]
    assert isinstance(model, ImpulseModel) and isinstance(model.name, str)
    _same_signature(model.run, ImpulseModel.run)
    run = {"t_end_s": 3.0 * model.duration_s, "n_outputs": 30}          # the pulse and after it
    first, again = (model.run(60.0, **run) for _ in range(2))
    assert isinstance(first, ImpulseResponse)
    assert set(_names(IMPULSE_CORE_COLUMNS)) <= set(first.history.columns)
    assert set(_names(IMPULSE_CORE_SUMMARY)) <= set(first.summary)
    assert first.summary["model"] == model.name and first.summary["alpha_per_s"] == 60.0
    np.testing.assert_allclose(first.history.time_s, pulse_times(**run), rtol=1e-12)
    np.testing.assert_array_equal(first.history.tip_uy_m, again.history.tip_uy_m)            # deterministic
    t, y = first.tip_signal()
    assert y[np.searchsorted(t, model.duration_s)] > 0.0              # pushed along +y by the +y pulse
    heavier = model.run(600.0, **run).history.tip_uy_m.abs().max()
    assert heavier < first.history.tip_uy_m.abs().max()               # more damping, less motion
    for bad, match in (({"alpha": -1.0}, "alpha"), ({"t_end_s": 0.0}, "t_end_s"), ({"n_outputs": 2.5}, "n_outputs")):
        with pytest.raises(InputError, match=match):
            model.run(**{"alpha": 10.0, **run, **bad})


def test_the_impulse_reductor_keeps_the_full_models_pulse_and_response(impulse_models):
    full, reduced = impulse_models["finger-fea"], impulse_models["finger-modal"]
    assert isinstance(reduced, ModalImpulseModel)
    assert (reduced.force_N, reduced.duration_s) == (full.force_N, full.duration_s)
    f = full.run(120.0, **IMPULSE_RUN).history.tip_uy_m.to_numpy()
    r = reduced.run(120.0, **IMPULSE_RUN).history.tip_uy_m.to_numpy()
    assert np.abs(r - f).max() < 0.05 * np.abs(f).max()


@pytest.mark.parametrize("label", ["fea", "rom-stations", "rom-face", "rom-linear"])
def test_contact_model_conformance(contact_models, contact_responses, label):
    model = contact_models[label]
    assert isinstance(model, ContactModel) and model.setup is COARSE
    _same_signature(model.run, ContactModel.run)
    response, again = contact_responses[label]
    assert isinstance(response, ContactResponse)
    assert set(_names(CONTACT_CORE_COLUMNS)) <= set(response.history.columns)
    assert set(_names(CONTACT_CORE_SUMMARY)) <= set(response.summary)
    s = response.summary
    assert (s["model"], s["alpha_per_s"], s["damping"]) == (model.name, 180.0, "global")
    np.testing.assert_allclose(response.history.time_s, pulse_times(**CONTACT_RUN), rtol=1e-12)
    history, core = response.core()
    assert {k: core[k] for k in contact_timing(history)} == contact_timing(history)
    h = response.history
    assert (h.reaction_force_N >= 0).all()
    assert (h.reaction_force_N + 1e-9 >= np.hypot(h.contact_force_x_N, h.contact_force_y_N)).all()
    assert (h.reaction_force_N[h.contact_nodes == 0] == 0).all()       # no contact point, no force
    counts = h.contact_nodes.to_numpy()                                 # FE: float column, ROM: int; both counts
    assert np.array_equal(counts, np.round(counts)) and (counts >= 0).all()
    assert s["contact_start_s"] is not None
    np.testing.assert_array_equal(h.reaction_force_N, again.history.reaction_force_N)        # deterministic
    for bad, match in (({"alpha": -1.0}, "alpha"), ({"damping": "local"}, "damping"), ({"t_end_s": 0.0}, "t_end_s"),
                       ({"n_outputs": 2.5}, "n_outputs")):
        with pytest.raises(InputError, match=match):
            model.run(**{"alpha": 10.0, "damping": "global", "t_end_s": 0.01, "n_outputs": 2, **bad})


def test_a_response_without_a_core_column_is_refused():
    names = _names(CONTACT_CORE_COLUMNS)
    with pytest.raises(InputError, match="contact_nodes"):
        ContactResponse(history=pd.DataFrame({c: [0.0] for c in names if c != "contact_nodes"}),
                        summary={c.name: None for c in CONTACT_CORE_SUMMARY})
    with pytest.raises(InputError, match="tip_uy_m"):
        ImpulseResponse(history=pd.DataFrame({"time_s": [0.1]}), summary={c.name: None for c in IMPULSE_CORE_SUMMARY})


def test_the_reduced_contact_models_touch_when_the_full_one_does(contact_responses):
    fea = contact_responses["fea"][0].summary["contact_start_s"]
    for label in ("rom-stations", "rom-face", "rom-linear"):
        assert contact_responses[label][0].summary["contact_start_s"] == pytest.approx(fea, abs=0.03), label


def test_the_contact_reductor_takes_a_full_model_only():
    with pytest.raises(InputError, match="FullContactModel.*ReducedContactModel"):
        reduce_contact_model(ReducedContactModel(COARSE, n_segments=5))
    reduced = reduce_contact_model(FullContactModel(COARSE), n_segments=5)
    assert reduced.setup is COARSE and reduced.chain.station_z_m.size == 6


def test_the_design_takes_either_model(contact_models):
    """The design's model run (its re-check and surrogate runs) gives every design output
    from the full model and from its reduction, which agree on the contact's timing."""
    short = DrumSetup(finger_section_elements=3, finger_elements_along=26, cycle_time_s=0.25)
    design = Design(alpha_per_s=180.0, x=short.finger_length_m, outputs={}, J=0.0)
    runs = {name: model_run(design, short, damping="relative", model_factory=factory)
            for name, factory in (("fea", lambda s: FullContactModel(s, object_stress=False)),
                                  ("rom", lambda s: reduce_contact_model(FullContactModel(s), n_segments=13)))}
    for name, run in runs.items():
        assert set(OUTPUTS) <= set(run["outputs"]), name
    assert runs["rom"]["outputs"]["contact_start_s"] == pytest.approx(runs["fea"]["outputs"]["contact_start_s"],
                                                                      abs=0.03)

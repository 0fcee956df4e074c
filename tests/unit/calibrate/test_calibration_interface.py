"""Both calibration models pass one conformance test of the interface the loop sees
(:class:`ccedi.calibrate.interface.CalibrationModel`), and each is made from rom's
reduction of its full FE model."""
import inspect

import numpy as np
import pytest
from conftest import ROOT

from ccedi.calibrate.contact_model import DrumContactModel
from ccedi.calibrate.experiment import load_experiment
from ccedi.calibrate.finger_modes import finger_basis
from ccedi.calibrate.fit import fit_baseline
from ccedi.calibrate.interface import CalibrationModel, FeaCorrected
from ccedi.calibrate.loop import calibration_model
from ccedi.calibrate.model import FingerModel
from ccedi.fea.material import NeoHookean
from ccedi.fea.mesh import sm_a
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.rom.contact_rom import ReducedContactModel
from ccedi.rom.modal import tip_modal_rom

RECORDS = {"impulse": ROOT / "data" / "measured" / "control_high.csv",
           "contact": ROOT / "data" / "contact" / "control_180.csv"}


@pytest.fixture(scope="module", params=sorted(RECORDS))
def model(request):
    return calibration_model(load_experiment(RECORDS[request.param]))


def _protocol_methods():
    return {name: member for name, member in vars(CalibrationModel).items()
            if not name.startswith("_") and inspect.isfunction(member)}


def test_each_record_kind_gets_its_model(model):
    expected = DrumContactModel if model.exp.kind == "contact" else FingerModel
    assert type(model) is expected
    assert isinstance(model, CalibrationModel)
    assert isinstance(model, FeaCorrected) == (model.exp.kind == "contact")


def test_every_method_takes_the_protocols_arguments(model):
    """Each method the loop calls binds the Protocol's positional arguments."""
    for name, member in _protocol_methods().items():
        params = [p for p in inspect.signature(member).parameters if p != "self"]
        inspect.signature(getattr(model, name)).bind(*params)


def test_the_baseline_prediction_is_the_records_signal_at_the_fit(model):
    """The baseline fit through the interface alone: a prediction of the record's length
    within a few noise levels of it, and calibrated inputs in SI units."""
    baseline = fit_baseline(model)
    prediction = model.predict(baseline.values)
    assert prediction.shape == model.exp.signal.shape
    rms = float(np.sqrt(np.mean((model.exp.signal - prediction) ** 2)))
    assert rms < 0.05 * float(np.ptp(model.exp.signal))
    calibrated = model.calibrated(baseline.values)
    assert calibrated["alpha_per_s"] == pytest.approx(baseline.values["alpha_per_s"])
    assert calibrated["E_Pa"] == pytest.approx(model.exp.finger.E_Pa * baseline.values["E_factor"])
    assert {p.name for p, _ in model.parameters(())} >= {"alpha_per_s", "E_factor"}


def test_the_impulse_models_modes_are_the_modal_reductors():
    """FingerModel's modes at the declared E are the modes the modal ROM of the same FE
    finger is made from: the same frequencies, and tip values whose squares are the ROM's
    gains (both from rom.modal.modal_basis)."""
    exp = load_experiment(RECORDS["impulse"])
    f = exp.finger
    basis = finger_basis(f.length_m, tuple(f.semi_axes_m), nu=f.nu, rho_kg_m3=f.rho_kg_m3, E_Pa=f.E_Pa)
    mesh = sm_a(length_m=f.length_m, semi_axes_m=tuple(f.semi_axes_m))
    fe = cantilever_model(mesh, NeoHookean(E=f.E_Pa, nu=f.nu, rho=f.rho_kg_m3),
                          pulses=[tip_pulse(mesh, [0.0, 1.0, 0.0], 0.01)])
    rom = tip_modal_rom(fe, n_modes=3)
    np.testing.assert_allclose(basis.omega_rad_s[:3], rom.omega_rad_s, rtol=1e-9)
    np.testing.assert_allclose(basis.tip[:3] ** 2, rom.gain, rtol=1e-9)


def test_the_contact_models_chain_is_the_contact_reductors():
    exp = load_experiment(RECORDS["contact"])
    model = DrumContactModel(exp)
    assert isinstance(model.rom, ReducedContactModel)

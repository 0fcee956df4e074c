"""One range per quantity, whichever way the value comes: the study TOML, a command-line
flag, a calibration sidecar or the Python API reject the same out-of-range value with the
same allowed range (``... = VALUE: must be in LO..HI (UNIT)``, one line)."""
import json
import re
import shutil

import pytest
from conftest import ROOT

from ccedi.calibrate.experiment import load_experiment
from ccedi.errors import InputError
from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.fea.contact.drum import DrumSetup
from ccedi.fea.material import NeoHookean
from ccedi.fea.mesh import sm_a
from ccedi.quantities import QUANTITIES
from ccedi.study.cli import main
from ccedi.study.config import validate

RECORD = ROOT / "data" / "measured" / "control_high.csv"


def _allowed(message):
    """The ``LO..HI (UNIT)`` part of a range message."""
    found = re.search(r"must be in (\S+\.\.\S+(?: \([^)]*\))?)", message)
    assert found and "\n" not in message, message
    return found.group(1)


def _toml(section, key, value):
    with pytest.raises(InputError) as err:
        validate({section: {key: value}})
    return str(err.value)


def _sidecar(tmp_path, edit):
    csv = tmp_path / "rec.csv"
    shutil.copy(RECORD, csv)
    meta = json.loads(RECORD.with_suffix(".json").read_text())
    edit(meta)
    csv.with_suffix(".json").write_text(json.dumps(meta))
    with pytest.raises(InputError) as err:
        load_experiment(csv)
    return str(err.value)


def _cli(argv, capsys):
    assert main(argv) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    return err


def _api(build):
    with pytest.raises(InputError) as err:
        build()
    return str(err.value)


def test_finger_length_has_one_range(tmp_path, capsys):
    messages = [_toml("finger", "impulse_length_in", 20.0),
                _cli(["impulse", "--length-in", "20", "--out", str(tmp_path / "o")], capsys),
                _sidecar(tmp_path, lambda m: m["finger"].update(length_in=20.0)),
                _api(lambda: sm_a(length_in=20.0)), _api(lambda: finger_impulse_model(length_in=20.0))]
    assert {_allowed(m) for m in messages} == {"1..12 (in)"}


def test_poisson_ratio_has_one_range(tmp_path):
    messages = [_toml("material", "nu", 0.5), _sidecar(tmp_path, lambda m: m["finger"].update(nu=0.5)),
                _api(lambda: NeoHookean(E=6.1e6, nu=0.5, rho=1000.0))]
    assert {_allowed(m) for m in messages} == {"0..0.499"}


def test_impulse_force_has_one_range(tmp_path, capsys):
    messages = [_toml("study", "impulse_force_N", 1e4),
                _cli(["impulse", "--force-N", "1e4", "--out", str(tmp_path / "o")], capsys),
                _sidecar(tmp_path, lambda m: m["load"].update(force_N=1e4)),
                _api(lambda: finger_impulse_model(force_N=1e4))]
    assert {_allowed(m) for m in messages} == {"0.0001..100 (N)"}


@pytest.mark.parametrize("key, quantity, value", [("friction", "friction", -0.1), ("omega_rad_s", "omega_rad_s", 0.0),
                                                  ("drum_radius_m", "drum_radius_m", 2.0)])
def test_drum_inputs_have_one_range(key, quantity, value):
    q = QUANTITIES[quantity]
    unit = f" ({q.unit})" if q.unit != "-" else ""
    messages = [_toml("drum", key, value), _api(lambda: DrumSetup(**{key: value}))]
    assert {_allowed(m) for m in messages} == {f"{q.lo:g}..{q.hi:g}{unit}"}

"""The compound catalogue: the bundled rows, the loss factor <-> alpha conversion and its
stated limit, a compound's alpha range for a finger, the rows CCEDI identifies, and the
reader's one-line errors on bad files."""
import csv
import io
import math
import re
from dataclasses import replace

import pytest
from conftest import ROOT

from ccedi.design.compounds import (
    CATALOGUE,
    COLUMNS,
    RANGES,
    alpha_from_loss_factor,
    catalogue_text,
    finger_damping,
    identified_compound,
    load_compounds,
    loss_factor_from_alpha,
    save_compound,
)
from ccedi.design.rubber import PAPER_MATCHED_ALPHA, alpha_cr_of_length
from ccedi.errors import InputError
from ccedi.fea.material import NeoHookean
from ccedi.rom.finger_identification import finger_omega1
from ccedi.units import inch_to_m

NAMED = ("natural_rubber", "neoprene", "nitrile", "sbr", "epdm", "silicone", "polyurethane", "butyl", "3m_isd_112")
"""The compounds the catalogue must hold (the last a viscoelastic damping polymer)."""


@pytest.fixture(scope="module")
def catalogue():
    return load_compounds()


def test_the_bundled_catalogue_holds_the_named_compounds_with_sources(catalogue):
    assert set(NAMED) <= set(catalogue)
    for c in catalogue.values():
        assert len(c.source) > 20, c.name
        assert 0.0 < c.E_min_Pa <= c.E_max_Pa and 0.0 <= c.tan_delta_min <= c.tan_delta_max
        assert c.band_min_hz <= c.band_max_hz and c.rho_kg_m3 > 0.0


def test_identified_rows_hold_their_alpha_converted_at_their_fingers_first_mode(catalogue):
    identified = [c for c in catalogue.values() if c.alpha_per_s is not None]
    assert identified
    for c in identified:
        omega_1 = finger_omega1(c.alpha_finger_length_in, material=NeoHookean(E=c.E_min_Pa, nu=0.49, rho=c.rho_kg_m3))
        assert c.tan_delta_min == pytest.approx(loss_factor_from_alpha(c.alpha_per_s, omega_1), rel=1e-3)
        assert c.band_min_hz == pytest.approx(omega_1 / (2.0 * math.pi), rel=1e-3)
    paper = catalogue["paper_finger_rubber"]
    assert paper.alpha_per_s == PAPER_MATCHED_ALPHA[paper.alpha_finger_length_in]


def test_loss_factor_is_twice_the_first_mode_damping_ratio_of_the_alpha():
    omega_1 = 89.4
    for tan_delta in (0.05, 0.3, 1.2):
        alpha = alpha_from_loss_factor(tan_delta, omega_1)
        assert alpha / (2.0 * omega_1) == pytest.approx(tan_delta / 2.0)      # zeta_1 = alpha / (2 omega_1)
        assert loss_factor_from_alpha(alpha, omega_1) == pytest.approx(tan_delta)


def test_a_compounds_alpha_range_follows_the_fingers_first_mode(catalogue):
    nr = catalogue["natural_rubber"]
    short, long_ = finger_damping(nr, 4.5), finger_damping(nr, 8.0)
    w_lo, w_hi = short.omega_1_rad_s
    assert w_lo == pytest.approx(finger_omega1(4.5, material=NeoHookean(E=nr.E_min_Pa, nu=0.49, rho=nr.rho_kg_m3)))
    stiff = finger_omega1(4.5, material=NeoHookean(E=nr.E_max_Pa, nu=0.49, rho=nr.rho_kg_m3))
    assert w_hi == pytest.approx(stiff, rel=1e-6)
    assert short.alpha_per_s == pytest.approx((nr.tan_delta_min * w_lo, nr.tan_delta_max * w_hi))
    assert short.zeta_1 == (nr.tan_delta_min / 2.0, nr.tan_delta_max / 2.0)
    assert long_.alpha_per_s[1] == pytest.approx(short.alpha_per_s[1] * (4.5 / 8.0) ** 2, rel=0.03)  # ~ 1 / L^2


def test_published_loss_factors_stay_far_below_the_papers_overdamped_finger(catalogue):
    """The documented limit: no handbook loss factor reaches the paper's 4.5-in alpha."""
    for c in catalogue.values():
        if c.alpha_per_s is None:
            assert finger_damping(c, 4.5).alpha_per_s[1] < 0.5 * alpha_cr_of_length(4.5), c.name
    assert PAPER_MATCHED_ALPHA[4.5] > alpha_cr_of_length(4.5)


def test_an_identified_compound_converts_its_alpha_at_the_sample_fingers_first_mode(tmp_path):
    row = identified_compound("sample", alpha_per_s=20.0, alpha_stderr_per_s=0.5, E_Pa=5e6, E_stderr_Pa=1e4,
                              rho_kg_m3=1100.0, length_m=inch_to_m(6.0), semi_axes_m=(0.012, 0.00845), nu=0.49,
                              source="sample.csv")
    omega_1 = finger_omega1(6.0, material=NeoHookean(E=5e6, nu=0.49, rho=1100.0))
    assert (row.tan_delta_min, row.tan_delta_max) == pytest.approx((19.0 / omega_1, 21.0 / omega_1))
    assert (row.E_min_Pa, row.E_max_Pa) == (5e6 - 2e4, 5e6 + 2e4)
    assert row.band_min_hz == row.band_max_hz == pytest.approx(omega_1 / (2.0 * math.pi))
    assert row.alpha_finger_length_in == pytest.approx(6.0) and row.alpha_source == "sample.csv"
    path = tmp_path / "compounds.csv"
    assert save_compound(path, row) is False
    assert save_compound(path, replace(row, name="other")) is False
    assert save_compound(path, replace(row, alpha_per_s=21.0)) is True
    back = load_compounds(path)
    assert list(back) == ["sample", "other"] and back["sample"] == replace(row, alpha_per_s=21.0)


def test_the_bundled_catalogue_survives_a_write_and_read(tmp_path, catalogue):
    path = tmp_path / "copy.csv"
    path.write_text(catalogue_text(catalogue.values()))
    assert load_compounds(path) == catalogue


def _edited(tmp_path, edit):
    text = CATALOGUE.read_text()
    path = tmp_path / "bad.csv"
    path.write_text(edit(text))
    return path


def _cell(text, name, column, value):
    """``text`` (a catalogue) with the cell ``column`` of compound ``name`` set to ``value``."""
    rows = list(csv.reader(io.StringIO(text)))
    rows[[r[0] for r in rows].index(name)][rows[0].index(column)] = value
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerows(rows)
    return out.getvalue()


BAD = {
    "missing column": (lambda t: t.replace("tan_delta_max", "tan_d_max", 1), "missing column(s) tan_delta_max"),
    "non-numeric": (lambda t: t.replace("neoprene,1.69e6", "neoprene,1.69 MPa", 1),
                    "line 3 (neoprene): E_min_Pa = '1.69 MPa': expected a number"),
    "min above max": (lambda t: t.replace("butyl,1.69e6,9.35e6", "butyl,9.35e7,9.35e6", 1),
                      "(butyl): E_min_Pa = 9.35e+07 is above E_max_Pa = 9.35e+06"),
    "out of range": (lambda t: t.replace("sbr,1.69e6,9.35e6,1150", "sbr,1.69e6,9.35e6,-1150", 1),
                     "(sbr): rho_kg_m3 = -1150.0: must be in 1..100000 (kg/m^3)"),
    "empty required cell": (lambda t: t.replace("epdm,1.69e6,9.35e6,1150,0.1", "epdm,1.69e6,9.35e6,1150,", 1),
                            "(epdm): column tan_delta_min is empty"),
    "name twice": (lambda t: t.replace("\nsbr,", "\nnitrile,", 1), "compound 'nitrile' is already on an earlier line"),
    "no source": (lambda t: _cell(t, "butyl", "source", " "), "(butyl): column source is empty"),
    "field count": (lambda t: t.replace("\nsbr,", "\nsbr,extra,", 1), "line 5 has 15 fields; the header has 14"),
    "unknown column": (lambda t: t.replace("notes", "note", 1), "unknown column 'note'"),
    "alpha without its finger": (lambda t: t.replace(",180,4.5,", ",180,,", 1),
                                 "alpha_per_s and alpha_finger_length_in are given together or not at all"),
}


@pytest.mark.parametrize("case", BAD)
def test_a_bad_catalogue_is_refused_in_one_line_naming_file_row_and_value(tmp_path, case):
    edit, says = BAD[case]
    path = _edited(tmp_path, edit)
    with pytest.raises(InputError) as err:
        load_compounds(path)
    message = str(err.value)
    assert says in message and str(path) in message and "\n" not in message, message


def test_a_missing_catalogue_and_a_bad_existing_one_are_refused(tmp_path):
    with pytest.raises(InputError, match="compound catalogue not found"):
        load_compounds(tmp_path / "none.csv")
    bad = _edited(tmp_path, BAD["non-numeric"][0])
    row = next(iter(load_compounds().values()))
    with pytest.raises(InputError, match="expected a number"):
        save_compound(bad, row)
    assert "1.69 MPa" in bad.read_text()                 # left as it was


def test_the_data_readme_states_the_catalogue_columns_and_ranges():
    """data/README.md's compounds.csv table lists every column, with the reader's ranges."""
    readme = (ROOT / "data" / "README.md").read_text()
    table = readme[readme.index("## `compounds.csv`"):]
    rows = re.findall(r"^\| ((?:`\w+`(?:, )?)+) \|[^|]*\|([^|]*)\|", table, re.MULTILINE)
    ranges = {name: rng.strip() for names, rng in rows for name in re.findall(r"`(\w+)`", names)}
    assert set(ranges) == set(COLUMNS)
    for column, quantity in RANGES.items():
        assert [float(x) for x in ranges[column].split("..")] == [quantity.lo, quantity.hi], column

"""Study TOML: the example loads back, and every bad input is one line naming the key."""
import pytest

from ccedi.errors import InputError
from ccedi.study.cli import main
from ccedi.study.config import SCHEMA, load


def _write(tmp_path, text):
    p = tmp_path / "study.toml"
    p.write_text(text)
    return p


def test_init_writes_an_example_that_loads_back_to_the_defaults(tmp_path, capsys):
    path = tmp_path / "study.toml"
    assert main(["init", str(path)]) == 0
    text = path.read_text()
    assert text.count("\n# ") >= sum(len(k) for k in SCHEMA.values())   # every key commented
    assert load(path) == load(None)
    assert main(["init", str(path)]) == 1                              # no silent overwrite
    assert "exists" in capsys.readouterr().err


@pytest.mark.parametrize("text, message", [
    ("[finger]\nlength_mm = 100\n", "[finger] length_mm: unknown key"),
    ("[finger]\nimpulse_length_mm = 100\n", "did you mean impulse_length_in"),
    ("[finger]\nimpulse_length_in = 20\n", "[finger] impulse_length_in = 20: must be in 1..12 (in)"),
    ("[study]\ncontact_alphas_per_s = [7.5, -1]\n", "[study] contact_alphas_per_s = -1: must be in 0..10000 (1/s)"),
    ("[study]\ndesign_fea_check = 1\n", "[study] design_fea_check = 1: must be bool"),
    ("[study]\nimpulse_t_end_s = \"long\"\n", "[study] impulse_t_end_s = 'long': must be float (s)"),
    ("[study]\nidentification_lengths_in = [4.5]\n",
     "[study] identification_lengths_in = [4.5]: must be a list of at least 2 float (in)"),
    ("[solver]\nsteps = 6\n", "unknown section [solver]"),
    ("[material]\nE_Pa = 1\n", "[material] E_Pa = 1: must be in 10000..1e+12 (Pa)"),
    ("[material]\nE_MPa = 6.1\n", "did you mean E_Pa"),
    ("[material]\nnu = 0.5\n", "[material] nu = 0.5: must be in 0..0.499"),
    ("[finger]\nsection_semi_axes_m = [0.012]\n", "must be a list of exactly 2 float (m)"),
    ("[drum]\nobject_center_m = [0.05, 0.05]\n", "[drum]: the object overlaps the drum"),
    ("[finger\n", "not valid TOML"),
])
def test_bad_input_is_one_line_naming_the_key(tmp_path, capsys, text, message):
    path = _write(tmp_path, text)
    with pytest.raises(InputError) as err:
        load(path)
    assert message in str(err.value) and "\n" not in str(err.value)
    assert main(["study", "--config", str(path), "--out", str(tmp_path / "r")]) == 1
    err_lines = capsys.readouterr().err.strip().splitlines()
    assert len(err_lines) == 1 and message in err_lines[0]
    assert not (tmp_path / "r").exists()


def test_finger_mesh_keys_resolve_relative_to_the_toml(tmp_path):
    from ccedi.fea.mesh.gmsh_fingers import write_tapered_finger
    from ccedi.study.config import finger_mesh, to_toml

    assert finger_mesh(load(None)) is None
    (tmp_path / "meshes").mkdir()
    write_tapered_finger(tmp_path / "meshes" / "f.msh", 8e-3)
    path = _write(tmp_path, '[finger]\nmesh = "meshes/f.msh"\nclamp = "clamp"\ntip = "z_max"\n')
    cfg = load(path)
    spec = finger_mesh(cfg)
    assert spec.path == str((tmp_path / "meshes" / "f.msh").resolve()) and spec.clamp == "clamp"
    assert spec.load().element_type == "tet10"
    again = tmp_path / "meshes" / "again.toml"        # the written inputs load from anywhere
    again.write_text(to_toml(cfg))
    assert load(again) == cfg


@pytest.mark.parametrize("text, message", [
    ('[finger]\nmesh = "missing.msh"\n', "[finger] mesh = 'missing.msh': no such file"),
    ('[finger]\nmesh_unit = "cm"\n', "[finger] mesh_unit = 'cm': must be one of m, mm"),
    ('[finger]\nbending_direction = "z"\n', "[finger] bending_direction = 'z': must be one of y, x"),
    ('[finger]\nclamp = ""\n', "[finger] clamp = '': must be a set name or one of x_min"),
    ('[finger]\ntip = 3\n', "[finger] tip = 3: must be str"),
])
def test_bad_finger_mesh_keys_are_one_line(tmp_path, text, message):
    with pytest.raises(InputError) as err:
        load(_write(tmp_path, text))
    assert message in str(err.value) and "\n" not in str(err.value)
    if "missing" in text:
        assert f"(relative to {tmp_path.resolve()})" in str(err.value)

"""The package's shape: one ``ccedi`` namespace, libraries below the application layer,
and a command line that answers ``--help`` without compiling anything."""
import ast
import os
import shutil
import subprocess
import sys
import zipfile

import pytest
from conftest import ROOT

LIBRARIES = ("fea", "rom", "design", "calibrate")
"""Top-level folders holding the libraries (ccedi.fea, ccedi.rom, ...)."""


def _imported_modules(path):
    """Absolute names of the modules a source file imports (relative imports resolved
    against its package, ccedi.<folder>)."""
    package = ["ccedi", path.parent.name]
    names = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else []))
            names.add(module)
            names.update(f"{module}.{alias.name}" for alias in node.names)
    return names


def test_the_walk_finds_imports_of_every_form(tmp_path):
    lib = tmp_path / "rom"
    lib.mkdir()
    src = lib / "m.py"
    src.write_text("import argparse\nfrom ccedi.study.config import load\nfrom ..study import run\n"
                   "def f():\n    from ccedi.study import report\n")
    names = _imported_modules(src)
    assert {"argparse", "ccedi.study.config", "ccedi.study.run", "ccedi.study.report"} <= names


@pytest.mark.parametrize("library", LIBRARIES)
def test_libraries_never_import_the_study_or_argparse(library):
    offenders = []
    for path in sorted((ROOT / library).rglob("*.py")):
        bad = {n for n in _imported_modules(path)
               if n == "argparse" or n == "ccedi.study" or n.startswith("ccedi.study.")}
        offenders += [f"{path.relative_to(ROOT)} imports {n}" for n in sorted(bad)]
    assert not offenders, "; ".join(offenders)


def test_help_imports_no_numba_kernel():
    code = ("import sys\nfrom ccedi.study.cli import main\n"
            "try:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
            "for sub in ('table1', 'contact', 'rom-check', 'calibrate', 'design', 'study'):\n"
            "    try:\n        main([sub, '--help'])\n    except SystemExit:\n        pass\n"
            "heavy = sorted(m for m in sys.modules if m.split('.')[0] in ('numba', 'llvmlite', 'casadi', 'dask'))\n"
            "print('HEAVY', heavy)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True).stdout
    assert "usage: ccedi" in out
    assert "HEAVY []" in out, out.splitlines()[-1]


def test_python_m_ccedi_is_the_command_line():
    out = subprocess.run([sys.executable, "-m", "ccedi", "--help"], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 0 and "usage: ccedi" in out.stdout and "study" in out.stdout


@pytest.mark.slow
def test_wheel_holds_only_ccedi_and_imports_beside_clashing_files(tmp_path):
    """A wheel built from the tree has ccedi/ and its dist-info at the top, nothing else;
    installed in a fresh venv, ``import ccedi.fea`` works from a directory that holds
    study.py, fea.py and design.py (which would shadow top-level packages of those names)."""
    tree = tmp_path / "tree"                       # a copy: building writes build/ into the tree it builds
    tree.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, tree / name)
    for folder in ("ccedi", *LIBRARIES, "study"):
        shutil.copytree(ROOT / folder, tree / folder, ignore=shutil.ignore_patterns("__pycache__"))
    wheels = tmp_path / "wheels"
    subprocess.run([sys.executable, "-m", "pip", "wheel", str(tree), "--no-deps", "-q", "-w", str(wheels)],
                   check=True, capture_output=True)
    (wheel,) = wheels.glob("ccedi-*.whl")
    tops = {name.split("/")[0] for name in zipfile.ZipFile(wheel).namelist()}
    assert {t for t in tops if not t.endswith(".dist-info")} == {"ccedi"}, sorted(tops)
    names = zipfile.ZipFile(wheel).namelist()
    for module in ("ccedi/fea/solvers/explicit.py", "ccedi/rom/modal.py", "ccedi/design/optimise.py",
                   "ccedi/calibrate/loop.py", "ccedi/study/cli.py", "ccedi/study/commands/fea.py", "ccedi/errors.py"):
        assert module in names
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    python = venv / "bin" / "python"
    subprocess.run([python, "-m", "pip", "install", "-q", "--no-deps", "--no-index", str(wheel)], check=True,
                   capture_output=True)
    work = tmp_path / "work"
    work.mkdir()
    for clash in ("study.py", "fea.py", "design.py"):
        (work / clash).write_text("raise ImportError('the working directory shadowed ccedi')\n")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    run = subprocess.run([python, "-c", "import ccedi.fea, ccedi.study, ccedi.design; print(ccedi.fea.__file__)"],
                         cwd=work, capture_output=True, text=True, env=env)
    assert run.returncode == 0, run.stderr
    assert str(venv) in run.stdout                       # the installed wheel, not the tree or the clashes

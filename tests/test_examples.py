"""The runnable examples under examples/ run and answer what they say."""
import subprocess
import sys
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_design_script_meets_the_designers_requirements():
    """The design script: a user-defined output with its own limit, the optimum re-checked
    (by the ROM here) and found to meet every requirement, its own included."""
    run = subprocess.run([sys.executable, str(EXAMPLES / "design_script.py"), "--grid", "6", "5"],
                         capture_output=True, text=True, timeout=900)
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    assert lines[0].startswith("optimum: alpha = ")
    assert any(line.startswith("Pareto front") for line in lines)
    assert lines[-1] == "re-check (contact ROM): meets every requirement"

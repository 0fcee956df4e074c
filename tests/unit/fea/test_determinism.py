"""Results depend on the inputs only, not on numba's cache state.

A process that compiles the kernels and one that loads them from numba's on-disk cache
must produce the same bits: an impulse run and a contact run on the drum, each done once
with an empty cache directory and once with the cache the first run wrote.
"""
import os
import re
import subprocess
import sys

import pytest

SCRIPT = """
import hashlib
from ccedi.fea.contact.drum import DrumSetup, FullContactModel
from ccedi.fea.cases.studies import impulse_study

history, _ = impulse_study(alphas=(70.0, 180.0), length_in=3.0, t_end_s=0.02, n_outputs=40)
contact = FullContactModel(DrumSetup(finger_section_elements=3, finger_elements_along=26),
                           object_stress=False).run(180.0, t_end_s=0.45, n_outputs=45).history
for name, frame in (("impulse", history), ("contact", contact)):
    for column in frame.columns:
        print(name, column, hashlib.sha256(frame[column].to_numpy().tobytes()).hexdigest())
"""


def _fingerprints(cache_dir):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir))
    out = subprocess.run([sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, timeout=600,
                         check=True)
    return [line for line in out.stdout.splitlines() if re.fullmatch(r"\S+ \S+ [0-9a-f]{64}", line)]   # no progress lines


@pytest.mark.slow
def test_compiled_and_cached_kernels_give_the_same_bits(tmp_path):
    cold = _fingerprints(tmp_path)
    assert any(tmp_path.rglob("*.nbi")), "the first run should have written numba's cache"
    warm = _fingerprints(tmp_path)
    assert len(cold) > 10
    differing = [a.rsplit(" ", 1)[0] for a, b in zip(cold, warm) if a != b]
    assert not differing, f"columns that differ between a cold and a warm cache: {differing}"

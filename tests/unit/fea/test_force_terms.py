"""The step's force terms: loops over terms written out for numba, an element kind added
without touching the step loop, and failures numbered across the terms."""
import subprocess
import sys
from collections import namedtuple

import numba as nb
import numpy as np
import pytest
from conftest import ROOT

from ccedi.errors import SolverError
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import Mesh, elliptical_cantilever
from ccedi.fea.mesh.tet_mesh import box_cantilever, split_hexes
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.fea.solvers import explicit
from ccedi.fea.solvers.force_terms import ForceTerm, unroll_terms

Scaled = namedtuple("Scaled", "kernel data")
Gain = namedtuple("Gain", "k")
Offset = namedtuple("Offset", "values limit")


@nb.njit
def _gain(x, data):
    return data.k * x, -1


@nb.njit
def _offset(x, data):
    return x + data.values.sum(), 0 if x > data.limit else -1


def _chain(terms, x):
    """Each term maps x on; the first that fails returns its index."""
    for term in terms:
        x, bad = term.kernel(x, term.data)
        if bad >= 0:
            return x, bad
    return x, -1


def _broken(terms, x):
    for term in terms:
        if x > 0.0:
            break
        x = term.kernel(x, term.data)[0]
    return x


def test_written_out_loop_gives_the_loop_s_results():
    """A tuple of terms of different types: the written-out function, compiled, returns
    what the plain loop returns, a return from inside the loop included."""
    terms = (Scaled(_gain, Gain(2.0)), Scaled(_offset, Offset(np.arange(3.0), 100.0)), Scaled(_gain, Gain(0.5)))
    compiled = nb.njit(unroll_terms(_chain, {"terms": 3}))
    for x in (1.0, 60.0):                     # 60: the offset term fails (2 x 60 + 3 > 100)
        assert compiled(terms, x) == _chain(terms, x)
    assert compiled(terms, 60.0)[1] == 0 and compiled(terms, 1.0) == (2.5, -1)


def test_loops_that_cannot_be_written_out_are_refused():
    with pytest.raises(ValueError, match="cannot be written out"):
        unroll_terms(_broken, {"terms": 2})
    with pytest.raises(ValueError, match="cannot be written out"):
        unroll_terms(_chain, {"other": 2})


Spring = namedtuple("Spring", "nodes X k")


@nb.njit
def _spring_forces(x, v, spring, material, f):
    """Springs of stiffness k from ``nodes`` to their reference positions: a force term."""
    w = 0.0
    for a in range(spring.nodes.shape[0]):
        n = spring.nodes[a]
        for i in range(3):
            d = x[n, i] - spring.X[n, i]
            f[n, i] += spring.k * d
            w += 0.5 * spring.k * d * d
    return np.inf, w, 0.0, 0.0, -1


def _tip_run(model, backend, spring_k=None):
    """Tip y-deflection and energy record of 2 ms of ``model``, straight through the step
    loop, with a spring term to ground on the tip nodes added to the run's terms."""
    mesh = model.mesh
    x, v = mesh.nodes.copy(), np.zeros_like(mesh.nodes)
    contact = explicit._contact_group(model, explicit.critical_time_step(model))
    control, state, nodes, internal, external, frame = explicit._step_data(model, x, v, 0.0, explicit.TSSFAC,
                                                                          contact, backend)
    if spring_k is not None:
        tip = mesh.node_sets["tip"]
        kernel = _spring_forces if backend == "numba" else _spring_forces.py_func
        spring = ForceTerm(kernel, Spring(tip, mesh.nodes, spring_k), len(tip), 0, explicit._INVERTED,
                           np.zeros((0, 3)))
        internal = internal._replace(terms=internal.terms + (spring,))
    advance = explicit._advance
    if backend == "numba":
        advance = explicit._advance_numba(tuple(term.kernel for term in internal.terms),
                                          tuple((term.kernel, term.impulse) for term in external))
        internal, external = explicit._compiled_terms(internal, external)
    energy = np.zeros(9)
    *_, status, _, _ = advance(0.0, 2e-3, 0.0, control, state, nodes, internal, external, frame, energy)
    assert status == explicit._OK
    return x[mesh.node_sets["tip"], 1].mean() - mesh.nodes[mesh.node_sets["tip"], 1].mean(), energy


def test_an_added_element_kind_needs_no_change_to_the_step_loop():
    """A spring term appended to the run's terms: both backends step it alike, it holds
    the tip back, and its stored energy is booked with the internal energy."""
    mesh = elliptical_cantilever(0.05, 3, 6)
    model = cantilever_model(mesh, RUBBER, alpha=50.0, pulses=[tip_pulse(mesh, [0.0, 2.0, 0.0], 2e-3)])
    free, _ = _tip_run(model, "numba")
    held, energy = _tip_run(model, "numba", spring_k=300.0)
    held_numpy, energy_numpy = _tip_run(model, "numpy", spring_k=300.0)
    assert 0.0 < held < 0.9 * free
    assert held_numpy == pytest.approx(held, rel=1e-9)
    assert np.allclose(energy_numpy, energy, rtol=1e-8, atol=0.0)
    stored = energy[explicit.KE] + energy[explicit.IE] + energy[explicit.HG] + energy[explicit.E_DAMP]
    assert stored + energy[explicit.E_BULK] == pytest.approx(energy[explicit.W_EXT], rel=0.02)


@pytest.mark.filterwarnings("ignore:invalid value encountered:RuntimeWarning")    # numpy tets: nodes of no tet
def test_an_inverted_tetrahedron_after_hexahedra_is_named_by_its_own_index():
    """Mixed mesh, hexahedra then 4-node tetrahedra: the step loop numbers a failed element
    over the solid elements (the tetrahedra's term starts after the hexahedra)."""
    box = box_cantilever(0.04, 0.01, 0.01, nx=2, ny=2, nz=6)
    part = split_hexes(Mesh(nodes=box.nodes, hexes=box.hexes[:4], node_sets=box.node_sets))
    mesh = Mesh(nodes=box.nodes, hexes=box.hexes[4:], tets4=part.tets4, node_sets=box.node_sets)
    model = cantilever_model(mesh, RUBBER)
    x0 = mesh.nodes.copy()
    c = mesh.tets4[7]
    x0[c[0]] = x0[c[1:4]].mean(axis=0) * 2 - x0[c[0]]          # corner 0 pushed through its face
    for backend in ("numba", "numpy"):
        with pytest.raises(SolverError, match=r"tet4 element \d+ inverted .* step 0"):
            explicit.run(model, 1e-4, x0=x0, backend=backend)


CACHED_LOOP = """
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import elliptical_cantilever
from ccedi.fea.mesh.tet_mesh import box_cantilever, quadratic_tets, split_hexes
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.fea.solvers import explicit
mesh = MESH
model = cantilever_model(mesh, RUBBER, alpha=50.0, pulses=[tip_pulse(mesh, [0.0, 2.0, 0.0], 2e-3)])
explicit.run(model, 1e-4, n_outputs=2, threads=1)
contact = explicit._contact_group(model, explicit.critical_time_step(model))
internal = explicit._internal_forces(model, "numba")
external = explicit._external_forces(model, contact, "numba")
loop = explicit._advance_numba(tuple(t.kernel for t in internal.terms), tuple((t.kernel, t.impulse) for t in external))
print(sum(loop.stats.cache_hits.values()), sum(loop.stats.cache_misses.values()))
"""


@pytest.mark.parametrize("mesh", ["elliptical_cantilever(0.05, 3, 6)",
                                  "quadratic_tets(split_hexes(box_cantilever(0.04, 0.01, 0.01, nx=2, ny=2, nz=6)))"],
                         ids=["hexahedra", "tetrahedra only"])
def test_the_compiled_step_loop_is_cached_on_disk(mesh):
    """A second process loads the step loop from numba's cache instead of compiling it
    (a process's first run then starts in about a second, not eight), and runs it: also
    for a finger without hexahedra, whose process never ran the parallel hexahedron
    kernel the cached loop calls into (it segfaulted before the kernel was loaded first)."""
    counts = []
    for _ in range(2):
        done = subprocess.run([sys.executable, "-c", CACHED_LOOP.replace("MESH", mesh)], capture_output=True,
                              text=True, cwd=ROOT)
        assert done.returncode == 0, (done.returncode, done.stderr[-2000:])
        counts.append(tuple(int(n) for n in done.stdout.split()[-2:]))
    hits, misses = counts[1]
    assert hits >= 1 and misses == 0, counts

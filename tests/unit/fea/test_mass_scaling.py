"""Mass scaling of the small tetrahedra: every element lifted to the target step, the mass
added where the scaled elements are and nowhere else, runs that many steps shorter with
the same response, and what it cannot do refused."""
from dataclasses import replace

import numpy as np
import pytest

from ccedi.errors import InputError
from ccedi.fea.material import NeoHookean
from ccedi.fea.mesh import Mesh, elliptical_cantilever
from ccedi.fea.mesh.tet_mesh import box_cantilever, quadratic_tets, split_hexes
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.fea.solvers.explicit import critical_time_step, element_stable_steps, run
from ccedi.fea.solvers.mass_scaling import AUTO_STEP_FRACTION, mass_scaled, step_target

MATERIAL = NeoHookean(6.1e6, 0.49, 1000.0)


def _pinched(quadratic=False):
    """A 4-node (or 10-node) tetrahedral beam with one interior node pushed towards its
    neighbour: a few elements much thinner than the rest, as a sliver in a user's mesh."""
    box = box_cantilever(0.04, 0.01, 0.01, nx=2, ny=2, nz=8)
    mesh = split_hexes(box)
    nodes = mesh.nodes.copy()
    centre = np.flatnonzero((np.abs(nodes[:, 0]) < 1e-12) & (np.abs(nodes[:, 1]) < 1e-12)
                            & (np.abs(nodes[:, 2] - 0.02) < 1e-12))[0]
    nodes[centre, 0] += 0.8 * 0.005                     # 80 % of the way to the next node along x
    mesh = Mesh(nodes=nodes, tets4=mesh.tets4, node_sets=mesh.node_sets)
    return quadratic_tets(mesh) if quadratic else mesh


def _model(mesh, **kw):
    return cantilever_model(mesh, MATERIAL, alpha=50.0, pulses=[tip_pulse(mesh, [0.0, 0.5, 0.0], 2e-3)], **kw)


TARGET = 0.33
"""The target step over the median element step of the pinched mesh: its six smallest
elements are below it (the default, AUTO_STEP_FRACTION, would add 7.6 % to this coarse
mesh's mass, and is refused)."""


@pytest.fixture(scope="module")
def scaled():
    model = _model(_pinched(quadratic=True))
    return (model, *mass_scaled(model, dt_target_s=TARGET * np.median(element_stable_steps(model))))


def test_every_element_reaches_the_target_and_only_the_small_ones_change(scaled):
    model, new, report = scaled
    before, after = element_stable_steps(model), element_stable_steps(new)
    assert before.min() < 0.8 * report.dt_target_s                # the pinch sets the step
    assert after.min() >= report.dt_target_s * (1.0 - 1e-6)
    assert report.dt_after_s == pytest.approx(after.min()) and report.speedup > 1.2
    factor = new.element_mass_scale
    assert 0 < report.scaled_elements == np.count_nonzero(factor > 1.0) < 0.2 * len(factor)
    assert np.all(factor[np.argsort(before)] == np.sort(factor)[::-1])      # the smaller, the more scaled


def test_a_target_that_needs_too_much_mass_is_refused():
    """The 4-node elements share their pressure at the nodes: the stiffest mode of the
    pinched mesh spans every element around the pinched node, and lifting the step to the
    default target would scale them all (about 4 times the mass). Refused, in one line."""
    model = _model(_pinched(quadratic=False))
    with pytest.raises(InputError, match=r"adds .* % to the finger's mass .* remesh"):
        mass_scaled(model)

def test_the_added_mass_sits_on_the_scaled_elements_nodes(scaled):
    """Mass is conserved element by element: the added mass is sum (s_e - 1) rho V_e, and
    nodes of no scaled element keep their mass exactly."""
    model, new, report = scaled
    group = model.tet4 if len(model.mesh.tets4) else model.tet10
    conn = model.mesh.tets4 if len(model.mesh.tets4) else model.mesh.tets10
    expected = float(np.sum((new.element_mass_scale - 1.0) * MATERIAL.rho * group.volume))
    assert report.added_mass_kg == pytest.approx(expected, rel=1e-12)
    assert report.added_mass_fraction == pytest.approx(expected / model.total_mass, rel=1e-12)
    touched = np.zeros(model.mesh.n_nodes, bool)
    touched[np.unique(conn[new.element_mass_scale > 1.0])] = True
    assert np.array_equal(new.mass[~touched], model.mass[~touched])
    assert np.all(new.mass[touched] > model.mass[touched])


def test_the_scaled_run_takes_fewer_steps_for_the_same_response(scaled):
    """The run's step follows the lifted element step, and the tip's response to the pulse
    (a few small elements carry little mass) stays within 2 % of its peak."""
    model, new, report = scaled
    assert critical_time_step(new) == pytest.approx(report.dt_after_s, rel=0.02)
    a = run(model, 6e-3, n_outputs=30, threads=1)
    b = run(new, 6e-3, n_outputs=30, threads=1)
    assert a.summary["steps"] / b.summary["steps"] == pytest.approx(report.speedup, rel=0.05)
    ya, yb = a.history["tip_uy_m"].to_numpy(), b.history["tip_uy_m"].to_numpy()
    assert np.abs(ya).max() > 0.0
    assert np.abs(ya - yb).max() < 0.02 * np.abs(ya).max()
    assert abs(report.frequency_change) < 0.01
    assert report.frequencies_after_hz[0] <= report.frequencies_before_hz[0]


def test_unit_factors_change_nothing():
    """element_mass_scale of ones builds the same model, bit for bit in a run."""
    plain = _model(_pinched())
    ones = replace(plain, element_mass_scale=np.ones(plain.mesh.n_elements))
    assert np.array_equal(plain.mass, ones.mass)
    a, b = run(plain, 1e-3, n_outputs=5, threads=1), run(ones, 1e-3, n_outputs=5, threads=1)
    assert a.history.equals(b.history)


def test_the_automatic_target_is_a_fraction_of_the_median_step():
    model = _model(_pinched(quadratic=True))
    assert step_target(model, "auto") == pytest.approx(AUTO_STEP_FRACTION * np.median(element_stable_steps(model)))


def test_a_step_already_met_scales_nothing():
    model = _model(_pinched())
    new, report = mass_scaled(model, dt_target_s=0.5 * element_stable_steps(model).min())
    assert new is model and report.scaled_elements == 0 and report.added_mass_kg == 0.0


@pytest.mark.parametrize("target, match", [("fast", "'fast'.*'auto'"), (-1e-6, "mass scaling step"),
                                           (float("nan"), "mass scaling step")])
def test_a_bad_target_is_refused(target, match):
    with pytest.raises(InputError, match=match):
        mass_scaled(_model(_pinched()), dt_target_s=target)


def test_hexahedra_are_not_scaled():
    mesh = elliptical_cantilever(0.05, 3, 6)
    model = _model(mesh)
    with pytest.raises(InputError, match="hexahedra are not scaled"):
        mass_scaled(model, dt_target_s=2.0 * critical_time_step(model))
    with pytest.raises(InputError, match="hexahedra's factors must be 1"):
        replace(model, element_mass_scale=np.full(mesh.n_elements, 2.0))


@pytest.mark.parametrize("make", [lambda n: np.ones(3), lambda n: np.full(n, 0.5), lambda n: np.full(n, np.nan)],
                         ids=["shape", "below one", "nan"])
def test_bad_factors_are_refused(make):
    model = _model(_pinched())
    with pytest.raises(InputError, match="element_mass_scale"):
        replace(model, element_mass_scale=make(model.mesh.n_elements))

"""Many runs of one mesh in one pass: the explicit solver with its SIMD lanes across runs.

A CCEDI search, a damping sweep, a grid of full-FEA checks around a design or an ensemble
runs one finger many times with a different damping, load or initial state. Here the runs
advance together: the runs' nodal arrays are stored runs innermost, ``(n_nodes, 3,
lanes)``, and the hexahedron kernel (:mod:`ccedi.fea.elements.hex8_lanes`) computes an
element for 4 or 8 runs at once, reading the element's constants once; the step update
loops over the lanes of each nodal value. The lanes are dealt into groups, one group per
thread (each core its own runs: the kernel and the loop release the GIL), each group with
its own arrays.

Every run is, bit for bit, the run :func:`ccedi.fea.solvers.explicit.run` makes alone:
each lane keeps its own time, its own CFL step and its own step count (a lane that reaches
an output time waits, unchanged, for the others), and every expression of the single run's
step loop is evaluated in the same order. A lane past the last run of its group repeats
that run and is discarded. ``tests/unit/fea/test_batch.py`` compares histories and final
states with single runs.

What may differ between the runs: alpha, the force pulses, the initial positions and
velocities. What they must share, else :func:`batch_refusal` says why not and the caller
runs them one by one: the mesh (hexahedra only), the material, beta, the supports, the
masses; no contact, no rotating frame, mass damping on the absolute velocity.
"""
import functools
import time as _time
from collections import namedtuple
from concurrent.futures import ThreadPoolExecutor

import numba as nb
import numpy as np

from ccedi.errors import InputError, SolverError
from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.elements.hex8_lanes import full_stiffness, lanes_kernel
from ccedi.fea.model import Model
from ccedi.fea.solvers.explicit import (
    _DIVERGED,
    _INVERTED,
    _OK,
    _STEP_TOO_LARGE,
    RunResult,
    SolidMaterial,
    _initial_energy,
    _initial_state,
    _internal_forces,
    _stable_step,
    check_status,
    output_points,
    output_row,
    run_plan,
    run_record,
)
from ccedi.fea.solvers.force_terms import E_BULK, E_DAMP, HG, IE, KE, W_EXT
from ccedi.fea.solvers.loads import pulse_loads
from ccedi.progress import progress_bar
from ccedi.threads import thread_count

LaneControl = namedtuple("LaneControl", "dt_user tssfac beta alpha")
LaneControl.__doc__ = """The step control of a group of lanes.

Attributes
----------
dt_user : float
    Fixed step [s]; 0.0 for the CFL-controlled step.
tssfac : float
    Scale factor of the CFL step [-].
beta : float
    Stiffness-proportional damping [s], shared.
alpha : (lanes,) ndarray
    Mass-proportional damping of each lane [1/s].
"""
LaneState = namedtuple("LaneState", "x v v_new f_int f_int_prev f_ext reaction")
LaneState.__doc__ = """Nodal state of a group of lanes, runs innermost (every field (n_nodes, 3, lanes)),
as :data:`ccedi.fea.solvers.explicit.State` is for one run.

Attributes
----------
x : ndarray
    Positions x^n [m].
v : ndarray
    Half-step velocities v^{n-1/2} [m/s].
v_new : ndarray
    Trial and then final v^{n+1/2} [m/s].
f_int : ndarray
    Internal forces of the step [N].
f_int_prev : ndarray
    Internal forces of the previous step [N] (stiffness damping).
f_ext : ndarray
    External forces of the step [N].
reaction : ndarray
    Support reactions [N].
"""
LaneNodes = namedtuple("LaneNodes", "mass mass3 inv_mass constrained v_pres")
LaneNodes.__doc__ = """The nodes' constants, shared by the lanes.

Attributes
----------
mass : (n_nodes,) ndarray
    Lumped masses [kg].
mass3 : (n_nodes, 3) ndarray
    The masses repeated for each direction [kg].
inv_mass : (n_nodes, 3) ndarray
    Their inverses [1/kg] (0 for a massless node).
constrained : (c,) int ndarray
    The fixed nodes.
v_pres : (n_nodes, 3) ndarray
    Their prescribed velocities [m/s] (zero).
"""
LaneLoads = namedtuple("LaneLoads", "nodes forces t_start t_end lane_start loaded external")
LaneLoads.__doc__ = """The lanes' force pulses (:data:`ccedi.fea.solvers.loads.PulseLoads`
of each lane, one after the other).

Attributes
----------
nodes : (p,) int ndarray
    Loaded node of each row.
forces : (p, 3) ndarray
    Its force while the pulse is on [N].
t_start, t_end : (p,) ndarray
    When the pulse switches on (inclusive) and off (exclusive) [s].
lane_start : (lanes + 1,) int ndarray
    Lane l's rows are ``lane_start[l]:lane_start[l + 1]``.
loaded : (k,) int ndarray
    The nodal values any pulse sets (``3 node + direction``, ascending).
external : (m,) int ndarray
    Those and the supported nodes' values, ascending: where the external forces and the
    reactions can be nonzero.
"""
LaneClock = namedtuple("LaneClock", "t dt_prev steps status info dt_seen")
LaneClock.__doc__ = """Each lane's clock (every field (lanes,)).

Attributes
----------
t : ndarray
    Time reached [s].
dt_prev : ndarray
    The last step [s].
steps : int ndarray
    Steps taken.
status : int ndarray
    The step loop's status (0: running).
info : int ndarray
    The failed element, when one failed.
dt_seen : ndarray
    Smallest step taken [s].
"""


def _lane_code(lanes):
    """Source of the step loop's per-node passes for ``lanes`` runs, each lane written out:
    in each node's pass every lane's loads and arithmetic come before its stores and the
    lanes' sums are scalars, so that LLVM joins the lanes into vector instructions (a loop
    over the lanes left each lane's load behind the previous lane's store, which LLVM
    cannot move without knowing the arrays apart)."""
    lane = range(lanes)

    def each(template, sep="; "):
        return sep.join(template.format(l=k) for k in lane)

    return f"""
def trial_velocities_{lanes}(vnf, vf, fef, fif, imf, a, Dt, inv_den, n3):
    {each("a{l} = a[{l}]")}
    {each("Dt{l} = Dt[{l}]")}
    {each("d{l} = inv_den[{l}]")}
    for q in range(n3):
        im = imf[q]
        j = np.uint64(q * {lanes})
        {each("r{l} = ((1.0 - a{l}) * vf[j + np.uint64({l})] + Dt{l} * (fef[j + np.uint64({l})] - fif[j + np.uint64({l})]) * im) * d{l}", chr(10) + 8 * " ")}
        {each("vnf[j + np.uint64({l})] = r{l}")}


def commit_{lanes}(vf, vnf, xf, mass3, dt, n3, mvb2, ke):
    {each("dt{l} = dt[{l}]")}
    {each("mvb2[{l}] = 0.0; ke[{l}] = 0.0")}
    for q in range(n3):
        m = mass3[q]
        j = np.uint64(q * {lanes})
        {each("vo{l} = vf[j + np.uint64({l})]; vn{l} = vnf[j + np.uint64({l})]; x{l} = xf[j + np.uint64({l})]", chr(10) + 8 * " ")}
        {each("b{l} = 0.5 * (vo{l} + vn{l})", chr(10) + 8 * " ")}
        {each("m{l} = mvb2[{l}] + m * b{l} * b{l}", chr(10) + 8 * " ")}
        {each("k{l} = ke[{l}] + m * vo{l} * vn{l}", chr(10) + 8 * " ")}
        {each("xn{l} = x{l} + dt{l} * vn{l}", chr(10) + 8 * " ")}
        {each("mvb2[{l}] = m{l}", chr(10) + 8 * " ")}
        {each("ke[{l}] = k{l}", chr(10) + 8 * " ")}
        {each("vf[j + np.uint64({l})] = vn{l}", chr(10) + 8 * " ")}
        {each("xf[j + np.uint64({l})] = xn{l}", chr(10) + 8 * " ")}
"""


@functools.cache
def _lane_passes(lanes):
    """The compiled per-node passes of :func:`_lane_code` for ``lanes`` runs:
    ``(trial_velocities, commit)``."""
    namespace = {"np": np, "__name__": __name__}
    exec(compile(_lane_code(lanes), __file__, "exec"), namespace)
    jit = nb.njit(cache=True, fastmath=FASTMATH, nogil=True, error_model="numpy")
    return jit(namespace[f"trial_velocities_{lanes}"]), jit(namespace[f"commit_{lanes}"])


@functools.cache
def step_loop(lanes):
    """The compiled step loop that advances a group of ``lanes`` runs (4 or 8).

    ``advance(t_stop, control, state, nodes, hexes, loads, clock, energy)`` steps every
    lane whose status is OK until its time reaches ``t_stop`` (the last step not
    shortened, as in :func:`ccedi.fea.solvers.explicit.run`); a lane that fails keeps its
    status and element in ``clock``. One dispatcher (and one cache entry) per width.

    Parameters
    ----------
    lanes : {4, 8}
        Runs per group.

    Returns
    -------
    numba dispatcher
    """
    kernel = lanes_kernel(lanes)
    trial_velocities, commit = _lane_passes(lanes)
    L = lanes

    @nb.njit(cache=True, fastmath=FASTMATH, nogil=True)
    def advance_lanes(t_stop, control, state, nodes, hexes, loads, clock, energy):
        x, v, v_new, f_int, f_int_prev, f_ext, reaction = state
        xf, vf, vnf = x.reshape(-1), v.reshape(-1), v_new.reshape(-1)
        fif, fpf, fef, rf = f_int.reshape(-1), f_int_prev.reshape(-1), f_ext.reshape(-1), reaction.reshape(-1)
        imf = nodes.inv_mass.reshape(-1)
        mass, mass3 = nodes.mass, nodes.mass3.reshape(-1)
        group, stiffness, material = hexes
        t, dt_prev, steps, status, info, dt_seen = clock
        dt_user, tssfac, beta, alpha = control
        n3 = x.shape[0] * 3
        res = np.empty((5, L))
        act = np.zeros(L, np.bool_)
        dt = np.zeros(L); Dt = np.ones(L); a = np.zeros(L); inv_den = np.ones(L); beta_rate = np.zeros(L)
        w_ext = np.zeros(L); mvb2 = np.zeros(L); ke = np.zeros(L); extra = np.zeros(L)
        while True:
            n_active = 0
            for ll in range(L):
                act[ll] = status[ll] == _OK and t[ll] < t_stop
                n_active += act[ll]
            if n_active == 0:
                return
            for j in range(fif.shape[0]):
                fif[j] = 0.0
            kernel(x, v, group, stiffness, material, 0, f_int, res)
            for ll in range(L):
                if not act[ll]:
                    continue
                if res[4, ll] >= 0.0:
                    status[ll] = _INVERTED; info[ll] = int(res[4, ll]); act[ll] = False
                    continue
                dt_stable = _stable_step(res[0, ll], beta)
                if dt_user > 0.0:
                    if dt_user > dt_stable:
                        status[ll] = _STEP_TOO_LARGE; dt_seen[ll] = dt_stable; act[ll] = False
                        continue
                    d = dt_user
                else:
                    d = tssfac * dt_stable
                dt_seen[ll] = min(dt_seen[ll], d)
                dt[ll] = d
                Dt[ll] = 0.5 * (dt_prev[ll] + d)
                beta_rate[ll] = beta / dt_prev[ll] if (beta > 0.0 and dt_prev[ll] > 0.0) else 0.0
                a[ll] = 0.5 * alpha[ll] * Dt[ll]
                inv_den[ll] = 1.0 / (1.0 + a[ll])
            for q in loads.loaded:            # the only entries a pulse ever set
                for ll in range(L):
                    fef[q * L + ll] = 0.0
            for ll in range(L):
                if act[ll]:
                    for p in range(loads.lane_start[ll], loads.lane_start[ll + 1]):
                        if loads.t_start[p] <= t[ll] and t[ll] < loads.t_end[p]:
                            for i in range(3):
                                f_ext[loads.nodes[p], i, ll] += loads.forces[p, i]
            # trial velocities v^{n+1/2} (every lane: an idle lane's are not committed)
            if beta > 0.0:
                for q in range(n3):
                    im = imf[q]
                    for ll in range(L):
                        j = q * L + ll
                        if beta_rate[ll] > 0.0:
                            fb = beta_rate[ll] * (fif[j] - fpf[j])
                            vnf[j] = ((1.0 - a[ll]) * vf[j] + Dt[ll] * (fef[j] - fif[j] - fb) * im) * inv_den[ll]
                        else:
                            vnf[j] = ((1.0 - a[ll]) * vf[j] + Dt[ll] * (fef[j] - fif[j]) * im) * inv_den[ll]
            else:
                trial_velocities(vnf, vf, fef, fif, imf, a, Dt, inv_den, n3)
            # supports: prescribed velocity and reaction
            for c in range(nodes.constrained.shape[0]):
                nd = nodes.constrained[c]
                m = mass[nd]
                for i in range(3):
                    for ll in range(L):
                        if act[ll]:
                            vref = 0.0
                            fb = beta_rate[ll] * (f_int[nd, i, ll] - f_int_prev[nd, i, ll])
                            vn = nodes.v_pres[nd, i]
                            v_new[nd, i, ll] = vn
                            reaction[nd, i, ll] = (m * (vn - v[nd, i, ll]) / Dt[ll]
                                                   + alpha[ll] * m * (0.5 * (vn + v[nd, i, ll]) - vref)
                                                   + f_int[nd, i, ll] + fb - f_ext[nd, i, ll])
            # works, kinetic energy and the move to the new state
            for ll in range(L):
                extra[ll] = 0.0
            if beta > 0.0:
                for q in range(n3):
                    for ll in range(L):
                        if beta_rate[ll] > 0.0:
                            j = q * L + ll
                            extra[ll] += beta_rate[ll] * (fif[j] - fpf[j]) * 0.5 * (vf[j] + vnf[j])
            # external work: only where a load or a support acts (elsewhere the term is
            # (0 + 0) b, which leaves the sum, never -0, unchanged), in node order
            for ll in range(L):
                w_ext[ll] = 0.0
            for q in loads.external:
                for ll in range(L):
                    j = q * L + ll
                    w_ext[ll] += (fef[j] + rf[j]) * (0.5 * (vf[j] + vnf[j]))
            if n_active == L:
                commit(vf, vnf, xf, mass3, dt, n3, mvb2, ke)
            else:                    # some lanes wait at the output time: leave their state
                for ll in range(L):
                    mvb2[ll] = 0.0; ke[ll] = 0.0
                for q in range(n3):
                    m = mass3[q]
                    for ll in range(L):
                        j = q * L + ll
                        vo = vf[j]
                        vn = vnf[j]
                        b = 0.5 * (vo + vn)
                        mvb2[ll] += m * b * b
                        ke[ll] += m * vo * vn
                        if act[ll]:
                            vf[j] = vn
                            xf[j] += dt[ll] * vn
            if beta > 0.0:
                for q in range(n3):
                    for ll in range(L):
                        if act[ll]:
                            fpf[q * L + ll] = fif[q * L + ll]
            for ll in range(L):
                if not act[ll]:
                    continue
                energy[ll, W_EXT] += Dt[ll] * w_ext[ll]
                energy[ll, E_DAMP] += Dt[ll] * (alpha[ll] * mvb2[ll] + extra[ll])
                energy[ll, E_BULK] += Dt[ll] * res[3, ll]
                energy[ll, KE] = 0.5 * ke[ll]
                energy[ll, IE] = res[1, ll]
                energy[ll, HG] = res[2, ll]
                if not (mvb2[ll] < np.inf):              # also catches NaN
                    status[ll] = _DIVERGED
                    continue
                t[ll] += dt[ll]
                dt_prev[ll] = dt[ll]
                steps[ll] += 1

    return advance_lanes


BATCH_MIN_RUNS = 4
"""Fewest runs worth a batch. A group of 4 lanes costs what 4 runs cost, whether they are
filled or not, on one core (70 ns per element and run in the kernel against 112 ns for the
single-run kernel): fewer runs go faster one by one, each on every core (SM-A, 0.2 s: a
single run on 2 threads 3.8 s, a group of 4 lanes on one 12.2 s; benchmarks/batch_speed.py)."""


def batch_refusal(models):
    """Why the models cannot advance in one batch, or None when they can.

    Parameters
    ----------
    models : sequence of Model
        The runs' models.

    Returns
    -------
    str or None
        The first difference found (it names the run and what differs).
    """
    if len(models) == 0:
        return "no models"
    if not all(isinstance(m, Model) for m in models):
        return "every model must be a fea.model.Model"
    first = models[0]
    mesh = first.mesh
    if len(mesh.hexes) == 0 or len(mesh.tets4) or len(mesh.tets10):
        return "batched runs take meshes of hexahedra only"
    for k, m in enumerate(models):
        if m.contact is not None or m.rotating is not None or m.rods:
            return f"run {k} has contact, a rotating frame or rods, which batched runs do not take"
        if m.damping != "global":
            return f"run {k} has {m.damping!r} damping; batched runs take global (absolute-velocity) damping"
        if m.mesh is not mesh and not (np.array_equal(m.mesh.nodes, mesh.nodes)
                                       and np.array_equal(m.mesh.hexes, mesh.hexes)):
            return f"run {k} has another mesh than run 0"
        if m.solid_constants != first.solid_constants or m.hourglass_coefficient != first.hourglass_coefficient:
            return f"run {k} has another material or hourglass coefficient than run 0"
        if m.beta != first.beta:
            return f"run {k} has beta = {m.beta:g} s, run 0 {first.beta:g} s: batched runs share beta"
        if not (np.array_equal(m.fixed_nodes, first.fixed_nodes) and np.array_equal(m.mass, first.mass)):
            return f"run {k} has other supports or masses than run 0"
    return None


def _lane_loads(models, supported):
    """The pulses of the lanes' models as :data:`LaneLoads` (``supported``: the fixed nodes)."""
    per_lane = [pulse_loads(m.pulses) for m in models]
    start = np.concatenate([[0], np.cumsum([len(p.nodes) for p in per_lane])]).astype(np.int64)
    nodes = np.concatenate([p.nodes for p in per_lane]).astype(np.int64)

    def values(of):
        return np.unique(3 * np.asarray(of, np.int64)[:, None] + np.arange(3)).astype(np.int64)

    return LaneLoads(nodes, np.concatenate([p.forces for p in per_lane]).reshape(-1, 3),
                     np.concatenate([p.t_start for p in per_lane]), np.concatenate([p.t_end for p in per_lane]),
                     start, values(nodes), values(np.concatenate([nodes, supported])))


def _group_size(n_runs, threads):
    """Lanes per group: 4 while the runs fill at most four per thread, else 8."""
    return 4 if n_runs <= 4 * threads else 8


def _run_group(models, starts, *, plan, lanes, points, bar):
    """Advance one group's runs (``models`` from ``starts``, their (x, v) with v zero on
    the supports; the lanes past them repeat the last) over every output time of ``plan``.
    Returns, per run, ``(rows, x, v, t, steps, dt_min, failure)``."""
    n_real = len(models)
    lane_models = list(models) + [models[-1]] * (lanes - n_real)
    lane_starts = list(starts) + [starts[-1]] * (lanes - n_real)
    first = lane_models[0]
    X = first.mesh.nodes
    n = len(X)

    def lanes_of(arrays):
        return np.ascontiguousarray(np.stack(arrays, axis=-1))

    x = lanes_of([s[0] for s in lane_starts])
    v = lanes_of([s[1] for s in lane_starts])
    state = LaneState(x, v, *(np.zeros((n, 3, lanes)) for _ in range(5)))
    mass3 = np.repeat(first.mass[:, None], 3, axis=1)
    nodes = LaneNodes(first.mass, mass3, np.divide(1.0, mass3, out=np.zeros_like(mass3), where=mass3 > 0.0),
                      np.unique(first.fixed_nodes).astype(np.int64), np.zeros((n, 3)))
    control = LaneControl(plan.dt_user, plan.tssfac, float(first.beta), np.array([m.alpha for m in lane_models]))
    group = first.hexahedra
    hexes = (group, full_stiffness(group), SolidMaterial(*first.solid_constants))
    clock = LaneClock(np.zeros(lanes), np.zeros(lanes), np.zeros(lanes, np.int64), np.zeros(lanes, np.int64),
                      np.zeros(lanes, np.int64), np.full(lanes, np.inf))
    energy = np.zeros((lanes, 9))
    loads = _lane_loads(lane_models, nodes.constrained)
    advance = step_loop(lanes)
    rows = [[] for _ in range(n_real)]
    failure = [None] * n_real
    for t_out in np.linspace(0.0, plan.t_end_s, plan.n_outputs + 1)[1:]:
        advance(t_out, control, state, nodes, hexes, loads, clock, energy)
        for k, m in enumerate(models):
            if failure[k] is not None:
                continue
            if clock.status[k] != _OK:
                failure[k] = (int(clock.status[k]), int(clock.info[k]), float(clock.t[k]), int(clock.steps[k]),
                              float(clock.dt_seen[k]))
                continue
            row, _ = output_row(m, points, t_out=t_out, t=clock.t[k], x=np.ascontiguousarray(x[:, :, k]),
                                v=np.ascontiguousarray(v[:, :, k]),
                                reaction=np.ascontiguousarray(state.reaction[:, :, k]), energy=energy[k],
                                contact=None)
            rows[k].append(row)
        if bar is not None:
            bar.update(1)
        if all(f is not None for f in failure):
            break
    return [(rows[k], np.ascontiguousarray(x[:, :, k]), np.ascontiguousarray(v[:, :, k]), float(clock.t[k]),
             int(clock.steps[k]), float(clock.dt_seen[k]), failure[k]) for k in range(n_real)]


def run_batch(models, t_end_s, *, n_outputs=400, x0=None, v0=None, tip_set="tip", reaction_set="root",
              threads=None, progress=False, max_steps=None):
    """Run several models of one mesh together, each result the same bits as its run alone.

    Parameters
    ----------
    models : sequence of Model
        The runs (:func:`batch_refusal` says what they must share).
    t_end_s : float
        End time of every run [s], > 0.
    n_outputs : int, optional
        Output rows of every run. Default 400.
    x0, v0 : sequence of (n_nodes, 3) array_like or None, optional
        Each run's initial positions [m] and velocities [m/s] (None: at rest in the
        reference configuration).
    tip_set, reaction_set : str, optional
        Node sets of the tip displacement and the summed reaction.
    threads : int, optional
        Threads (each advances its own runs; :func:`ccedi.threads.thread_count`).
    progress : bool, optional
        Show a progress bar over the groups' output times.
    max_steps : int, optional
        Step budget of each run (:func:`ccedi.fea.solvers.budget.step_budget`).

    Returns
    -------
    list of RunResult
        In the order of ``models``; equal to :func:`ccedi.fea.solvers.explicit.run` of
        each (its ``wall_time_s`` is the batch's, shared).

    Raises
    ------
    InputError
        The models cannot run in one batch (the reason), or an argument is out of range.
    SolverError
        A run failed (the first failed run is named; the others' results are lost with it,
        as when a sweep of single runs stops at a failed run).
    """
    models = list(models)
    reason = batch_refusal(models)
    if reason is not None:
        raise InputError(f"these runs cannot be batched: {reason}")
    n_threads = thread_count(threads)
    # one plan serves every run: it depends only on what batch_refusal made them share
    plan = run_plan(models[0], t_end_s, n_outputs=n_outputs, dt_s=None, max_steps=max_steps)
    X = models[0].mesh.nodes
    free = np.ones(len(X))
    free[models[0].fixed_nodes] = 0.0
    starts = []
    for k in range(len(models)):
        xk = X.copy() if x0 is None or x0[k] is None else _initial_state(f"x0[{k}] (initial positions, m)", x0[k],
                                                                         X.shape)
        vk = np.zeros_like(X) if v0 is None or v0[k] is None else _initial_state(
            f"v0[{k}] (initial velocities, m/s)", v0[k], X.shape)
        starts.append((xk, vk * free[:, None]))
    # initial energies here, not in the group threads: the hexahedron kernel they use is
    # numba-parallel, which numba's default (workqueue) threading layer runs from one thread at a time
    internal = _internal_forces(models[0], "numba")
    energy_0 = [_initial_energy(m, x, v, internal) for m, (x, v) in zip(models, starts)]
    lanes = _group_size(len(models), n_threads)
    groups = [list(range(i, min(i + lanes, len(models)))) for i in range(0, len(models), lanes)]
    points = output_points(models[0].mesh, tip_set, reaction_set)
    wall0 = _time.perf_counter()
    bar = progress_bar(total=len(groups) * plan.n_outputs, desc=f"{len(models)} runs, t_end {plan.t_end_s:g} s",
                       unit="output") if progress else None
    try:
        with ThreadPoolExecutor(max_workers=min(n_threads, len(groups))) as pool:
            futures = [pool.submit(_run_group, [models[k] for k in g], [starts[k] for k in g], plan=plan,
                                   lanes=lanes, points=points, bar=bar) for g in groups]
            outcomes = [item for f in futures for item in f.result()]
    finally:
        if bar is not None:
            bar.close()
    wall = _time.perf_counter() - wall0
    results = []
    for k, (m, outcome) in enumerate(zip(models, outcomes)):
        rows, x, v, t, steps, dt_min, failure = outcome
        if failure is not None:
            status, info, t_fail, steps_fail, dt_seen = failure
            try:
                check_status(m.mesh, status, info, t=t_fail, steps=steps_fail, dt_seen=dt_seen,
                             dt_user=plan.dt_user)
            except SolverError as error:
                raise SolverError(f"run {k} of the batch (alpha = {m.alpha:g} 1/s): {error}") from None
        history, summary = run_record(m, plan, rows, extra_columns=[], energy_0=energy_0[k], t_final=t,
                                      steps=steps, dt_min=dt_min, wall=wall, backend="numba", threads=n_threads)
        summary["batch_runs"] = len(models)
        results.append(RunResult(history=history, summary=summary, x=x, v=v, snapshots=[]))
    return results

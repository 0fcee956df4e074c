"""Explicit dynamics: central difference with Rayleigh damping and a CFL time step.

Equation of motion, paper Eq. (1) with Eq. (2): ``M a + (alpha M + beta K) v + f_int(x) = f_ext``.

Update from t^n to t^{n+1} = t^n + dt^{n+1/2} (variable step, lumped mass m)::

    Dt^n = (dt^{n-1/2} + dt^{n+1/2}) / 2
    v^{n+1/2} = [(1 - alpha Dt/2) v^{n-1/2} + Dt (f_ext - f_int - f_beta) / m] / (1 + alpha Dt/2)
    x^{n+1}  = x^n + dt^{n+1/2} v^{n+1/2}

The mass-proportional term is centred (average of the two half-step velocities), so it
adds no stability limit: any alpha >= 0 is stable. The stiffness-proportional force is
``f_beta = beta K v ~ beta (f_int^n - f_int^{n-1}) / dt^{n-1/2}``; it lowers the stable
step to ``dt <= (2/w_max)(sqrt(1 + xi^2) - xi)``, ``xi = beta w_max / 2``, ``w_max = 2/dt_cfl``.

Time step, paper Eq. (5): ``dt = TSSFAC x min_e dt_e`` (TSSFAC = 0.9), recomputed every step
on the deformed mesh. Energies are accumulated so that
``E0 + W_ext = KE + IE + HG + E_damping + E_bulk`` (E0 the energy of the initial state;
W_ext the work of the loads, the supports and the contact forces), which every run checks
(:func:`ccedi.fea.solvers.validity.energy_balance_error`). The works are those of the forces at
t^n on the mid-step velocity ``(v^{n-1/2} + v^{n+1/2}) / 2``, KE at t^n is
``sum m v^{n-1/2} . v^{n+1/2} / 2`` (the kinetic part of the energy central differences
conserve; the square of the mid-step velocity would miss up to 80 % of the energy of a
mode near the stability limit).

The step loop is written once (``_advance``) and knows no element kind and no load: it
sees the forces through the force terms of :mod:`ccedi.fea.solvers.force_terms`. Each
step it zeroes f_int and lets every internal term (hexahedra, 4-node and 10-node
tetrahedra, rods) add its forces and return its stable step and energies; zeroes f_ext
and lets every external term (force pulses, contact) add its forces; and, once the trial
velocities are known, calls every external term's impulse (Coulomb friction). The run
builds the terms (``_internal_forces``, ``_external_forces``): a new element kind or load
is a kernel of the terms' contract, its data and one more term there. The loop takes its
data in a few groups: the step control (size and damping), the nodal state, the nodes'
constants, the internal and the external terms, the rotating frame and the energy record.
It is compiled by numba with the numba kernels, its loops over the terms written out term
by term and cached on disk (``_advance_numba``), and run as plain Python with the numpy reference kernels
(``backend="numpy"``), which the tests compare.
"""
import functools
import hashlib
import time as _time
from collections import namedtuple
from dataclasses import dataclass, field

import numba as nb
import numpy as np
import pandas as pd

from ccedi.errors import InputError, SolverError, require_finite_positive
from ccedi.fea.contact.penalty import (
    PLANE,
    STEP_SHRINK,
    ContactGroup,
    contact_damping,
    penalty_stiffness,
)
from ccedi.fea.elements.fastmath import FASTMATH
from ccedi.fea.elements.hex8 import characteristic_length as hex_characteristic_length
from ccedi.fea.elements.hex8 import element_geometry
from ccedi.fea.elements.hex8_kernels import SolidMaterial
from ccedi.fea.elements.rod import rod_max_stress
from ccedi.fea.elements.tet10 import characteristic_length as tet10_characteristic_length
from ccedi.fea.elements.tetra import deformation_gradients_numba, min_altitude
from ccedi.fea.material import max_von_mises_of
from ccedi.fea.mesh import element_name
from ccedi.fea.model import Model, face_node_weights
from ccedi.fea.solvers.budget import STEPS_ENV, check_outputs, step_budget
from ccedi.fea.solvers.force_terms import (
    E_BULK,
    E_DAMP,
    E_PENALTY,
    HG,
    IE,
    KE,
    W_EXT,
    W_FRICTION,
    W_NORMAL,
    ExternalTerm,
    ForceTerm,
    InternalForces,
    RodGroup,
    contact_term,
    contact_term_numpy,
    friction_impulse,
    hex_term,
    hex_term_numpy,
    no_impulse,
    rod_term,
    rod_term_numpy,
    tet4_term,
    tet4_term_numpy,
    tet10_term,
    tet10_term_numpy,
    unroll_terms,
)
from ccedi.fea.solvers.loads import pulse_forces, pulse_loads
from ccedi.fea.solvers.prescribed import prescribed_rotation
from ccedi.fea.solvers.rotating_frame import RotatingFrame, frame_velocity
from ccedi.fea.solvers.validity import issue, max_log_strain, run_checks, run_label
from ccedi.progress import progress_bar
from ccedi.threads import thread_count

TSSFAC = 0.9
"""Time-step scale factor of paper Eq. (5)."""

# step loop status (the energy record's slots: ccedi.fea.solvers.force_terms)
_OK, _INVERTED, _DIVERGED, _STEP_TOO_LARGE, _FOLDED = 0, 1, 2, 3, 4

# The step loop's data, bundled by role (numba takes each as a heterogeneous tuple).
State = namedtuple("State", "x v v_new f_int f_int_prev f_ext reaction f_bulk")
State.__doc__ = """Nodal state of the step loop, updated in place (every field (n_nodes, 3)).

Attributes
----------
x : (n_nodes, 3) ndarray
    Current positions x^n [m].
v : (n_nodes, 3) ndarray
    Half-step velocities v^{n-1/2} [m/s].
v_new : (n_nodes, 3) ndarray
    Trial and then final half-step velocities v^{n+1/2} [m/s].
f_int : (n_nodes, 3) ndarray
    Internal forces f_int(x^n) of this step [N].
f_int_prev : (n_nodes, 3) ndarray
    Internal forces of the previous step [N] (for the stiffness damping beta K v).
f_ext : (n_nodes, 3) ndarray
    External forces of this step, pulses plus contact [N].
reaction : (n_nodes, 3) ndarray
    Support reactions of the constrained nodes [N] (zero on free nodes).
f_bulk : (n_nodes, 3) or (0, 3) ndarray
    The bulk-viscosity part of f_int that the force terms report in arrays of their
    own (the tetrahedra), summed [N]; empty when no term does.
"""
Nodes = namedtuple("Nodes", "X mass mass3 inv_mass free constrained v_pres")
Nodes.__doc__ = """Per-node constants of the step loop and the prescribed velocities.

Attributes
----------
X : (n_nodes, 3) ndarray
    Reference positions [m].
mass : (n_nodes,) ndarray
    Lumped nodal masses [kg].
mass3 : (n_nodes, 3) ndarray
    The masses repeated for each direction [kg].
inv_mass : (n_nodes, 3) ndarray
    Their inverses [1/kg] (0 for a massless node, which must be constrained).
free : (n_nodes,) ndarray
    1.0 for a free node, 0.0 for a constrained (fixed or rotating) one.
constrained : (c,) int ndarray
    Indices of the constrained nodes.
v_pres : (n_nodes, 3) ndarray
    Prescribed velocities of the constrained nodes [m/s] (zero for fixed nodes,
    updated every step for nodes carried by the rotating frame).
"""
Damping = namedtuple("Damping", "alpha beta relative")
Damping.__doc__ = """Rayleigh damping ``C = alpha M + beta K``.

Attributes
----------
alpha : float
    Mass-proportional coefficient [1/s].
beta : float
    Stiffness-proportional coefficient [s].
relative : bool
    True: the mass damping acts on the velocity relative to the rotating frame;
    False: on the absolute velocity.
"""
StepControl = namedtuple("StepControl", "dt_user tssfac damping")
StepControl.__doc__ = """How the step is taken: its size and its damping.

Attributes
----------
dt_user : float
    Fixed step [s]; 0.0 for the CFL-controlled step ``tssfac x`` stable step.
tssfac : float
    Scale factor of the CFL step [-] (TSSFAC, times STEP_SHRINK with contact).
damping : Damping
    Rayleigh damping.
"""
@nb.njit(cache=True, fastmath=FASTMATH)
def _stable_step(dte, beta):
    """Stable step [s] of the CFL step dte [s] lowered for stiffness damping beta [s]."""
    if beta > 0.0:
        xi = beta / dte
        return dte * (np.sqrt(1.0 + xi * xi) - xi)
    return dte


@nb.njit(cache=True, fastmath=FASTMATH)
def _trial_velocities(state, nodes, damping, frame, Dt, beta_rate):
    """v^{n+1/2} of every node without friction, into v_new; support reactions.

    Mass damping acts on v - v_ref, with v_ref = 0 (``global``, absolute velocity) or the
    velocity of the rotating frame at the node, omega axis x (x - c) (``relative``). Every
    node first gets the free update (one loop over the flat arrays, which LLVM compiles
    to SIMD instructions); the frame's term is then added to the free nodes, and the
    constrained nodes get their prescribed velocity and reaction."""
    v, v_new, f_ext, f_int, f_int_prev = (state.v.reshape(-1), state.v_new.reshape(-1), state.f_ext.reshape(-1),
                                          state.f_int.reshape(-1), state.f_int_prev.reshape(-1))
    inv_mass = nodes.inv_mass.reshape(-1)
    a = 0.5 * damping.alpha * Dt
    inv_den = 1.0 / (1.0 + a)
    if beta_rate > 0.0:
        for j in range(v.shape[0]):
            fb = beta_rate * (f_int[j] - f_int_prev[j])
            v_new[j] = ((1.0 - a) * v[j] + Dt * (f_ext[j] - f_int[j] - fb) * inv_mass[j]) * inv_den
    else:
        for j in range(v.shape[0]):
            v_new[j] = ((1.0 - a) * v[j] + Dt * (f_ext[j] - f_int[j]) * inv_mass[j]) * inv_den
    if damping.relative:
        x, free = state.x, nodes.free
        for n in range(x.shape[0]):
            if free[n] > 0.0:
                vr0, vr1, vr2 = frame_velocity(x, n, frame.center, frame.axis, frame.omega)
                v_new[3 * n] += 2.0 * a * vr0 * inv_den
                v_new[3 * n + 1] += 2.0 * a * vr1 * inv_den
                v_new[3 * n + 2] += 2.0 * a * vr2 * inv_den
    _constrained_velocities(state, nodes, damping, frame, Dt, beta_rate)


@nb.njit(cache=True, fastmath=FASTMATH)
def _constrained_velocities(state, nodes, damping, frame, Dt, beta_rate):
    """Prescribed v^{n+1/2} of the constrained nodes, and the reaction the support supplies:
    ``r = m (v_pres - v) / Dt + alpha m (vb - v_ref) + f_int + f_beta - f_ext``."""
    v, v_new, x, f_ext, f_int, f_int_prev, reaction = (state.v, state.v_new, state.x, state.f_ext, state.f_int,
                                                       state.f_int_prev, state.reaction)
    mass, v_pres = nodes.mass, nodes.v_pres
    alpha, relative = damping.alpha, damping.relative
    for c in range(nodes.constrained.shape[0]):
        n = nodes.constrained[c]
        m = mass[n]
        vr0, vr1, vr2 = frame_velocity(x, n, frame.center, frame.axis, frame.omega) if relative else (0.0, 0.0, 0.0)
        for i in range(3):
            vref = vr0 if i == 0 else (vr1 if i == 1 else vr2)
            fb = beta_rate * (f_int[n, i] - f_int_prev[n, i])
            vn = v_pres[n, i]
            v_new[n, i] = vn
            reaction[n, i] = (m * (vn - v[n, i]) / Dt + alpha * m * (0.5 * (vn + v[n, i]) - vref)
                              + f_int[n, i] + fb - f_ext[n, i])


@nb.njit(cache=True, fastmath=FASTMATH)
def _commit(state, nodes, damping, frame, Dt, dt, beta_rate):
    """Move to the new state: x^{n+1} = x^n + dt v^{n+1/2}. Returns the step's external
    work and damping work [J] (forces times the mid-step velocity
    ``vb = (v^{n-1/2} + v^{n+1/2}) / 2``) and twice the kinetic energy at t^n [J],
    ``m v^{n-1/2} . v^{n+1/2}``: the kinetic part of the energy central differences
    conserve (exactly for a linear undamped system; ``m vb^2`` differs from it by
    ``(dt a)^2 m / 4``, up to 80 % of a mode's energy near the stability limit), and
    ``sum m vb^2`` [J] (inf or NaN once the motion diverges).

    One pass over the flat arrays computes the three sums (in index order, so the same
    bits every run) and moves the state: the pass is bound by the memory traffic of the
    nodal arrays (four interleaved partial sums in one pass and the move in another took
    2.6 times as long on the 8-in finger); the frame's share of the damping work
    (relative damping) and the stiffness-damping work are added after."""
    v, v_new, x, f_ext, reaction = (state.v.reshape(-1), state.v_new.reshape(-1), state.x.reshape(-1),
                                    state.f_ext.reshape(-1), state.reaction.reshape(-1))
    mass = nodes.mass3.reshape(-1)
    w_ext = 0.0                                  # external work
    mvb2 = 0.0                                   # m vb^2
    ke = 0.0                                     # m v^{n-1/2} v^{n+1/2}
    extra = _extra_damping_power(state, nodes, damping, frame, beta_rate)     # before v is overwritten
    for j in range(v.shape[0]):
        vo = v[j]
        vn = v_new[j]
        b = 0.5 * (vo + vn)
        w_ext += (f_ext[j] + reaction[j]) * b
        mvb2 += mass[j] * b * b
        ke += mass[j] * vo * vn
        v[j] = vn
        x[j] += dt * vn
    w_damp = damping.alpha * mvb2 + extra
    if damping.beta > 0.0:
        state.f_int_prev[:] = state.f_int
    return Dt * w_ext, Dt * w_damp, ke, mvb2


@nb.njit(cache=True, fastmath=FASTMATH)
def _extra_damping_power(state, nodes, damping, frame, beta_rate):
    """Power [W] of the damping forces beyond ``alpha m vb``, on the mid-step velocity vb:
    ``-alpha m v_ref . vb`` of relative damping (v_ref the rotating frame's velocity) and
    the stiffness damping ``f_beta . vb``. Called before v is overwritten."""
    p = 0.0
    v, v_new = state.v, state.v_new
    if damping.relative:
        mass = nodes.mass
        for n in range(v.shape[0]):
            vr0, vr1, vr2 = frame_velocity(state.x, n, frame.center, frame.axis, frame.omega)
            p -= damping.alpha * mass[n] * (vr0 * 0.5 * (v[n, 0] + v_new[n, 0]) + vr1 * 0.5 * (v[n, 1] + v_new[n, 1])
                                            + vr2 * 0.5 * (v[n, 2] + v_new[n, 2]))
    if beta_rate > 0.0:
        f_int, f_int_prev = state.f_int, state.f_int_prev
        for n in range(v.shape[0]):
            for i in range(3):
                p += beta_rate * (f_int[n, i] - f_int_prev[n, i]) * 0.5 * (v[n, i] + v_new[n, i])
    return p


@nb.njit(cache=True, fastmath=FASTMATH)
def _zero(a):
    """Set the (n, 3) array ``a`` to zero, in one loop over its flat memory (0.34 against
    0.57 us for ``a[:] = 0.0`` on SM-A's 1100 nodes)."""
    flat = a.reshape(-1)
    for j in range(flat.shape[0]):
        flat[j] = 0.0


@nb.njit(cache=True, fastmath=FASTMATH)
def _accumulate(total, part):
    """``total += part`` element by element (both (n, 3))."""
    for n in range(total.shape[0]):
        for i in range(3):
            total[n, i] += part[n, i]


@nb.njit(cache=True, fastmath=FASTMATH)
def _bulk_work(f_bulk, v, v_new):
    """Power [W] of the bulk-viscosity forces ``f_bulk`` the force terms report (the
    tetrahedra's, a part of the internal force, so positive when dissipating) on the
    mid-step velocity, ``sum f_bulk . (v^{n-1/2} + v^{n+1/2}) / 2``: the dissipation
    consistent with how the run measures every other work (the element power
    ``-q e_v v`` at v^{n-1/2} overstates it when the highest modes ring)."""
    p = 0.0
    for n in range(v.shape[0]):
        for i in range(3):
            p += f_bulk[n, i] * 0.5 * (v[n, i] + v_new[n, i])
    return p


@nb.njit(cache=True, fastmath=FASTMATH)
def _record_energy(energy, w_ext, w_damp, bulk, ke, w_int, w_hg):
    """Accumulate the step's works [J] into ``energy``; store KE, IE, HG [J] of t^n."""
    energy[W_EXT] += w_ext
    energy[E_DAMP] += w_damp
    energy[E_BULK] += bulk
    energy[KE] = 0.5 * ke
    energy[IE] = w_int
    energy[HG] = w_hg


def _advance(t, t_stop, dt_prev, control, state, nodes, internal, external, frame, energy):
    """Advance until t >= t_stop (the last step is not shortened: cutting a step to land on
    an output time perturbs the highest mode and, repeated, can destabilise a mesh whose
    CFL estimate is tight). Returns (t, dt_prev, steps, status, info, dt_min_seen).

    ``control``, ``state``, ``nodes``, ``internal`` (:data:`InternalForces`: the
    internal force terms and the solids' material), ``external`` (tuple of
    :data:`ExternalTerm`) and ``frame`` are the groups of :func:`_step_data`, ``energy``
    the energy record. The loop knows no element kind and no load: every step it zeroes
    f_int and lets each internal term add its forces (:mod:`ccedi.fea.solvers.force_terms`),
    the step being the smallest of the terms' stable steps; zeroes f_ext and lets each
    external term add its forces; and after the trial velocities calls each external
    term's impulse. A failed element stops it with its term's status and index
    (``term.first`` plus the kernel's index). Compiled (:func:`_advance_numba`), the
    loops over the terms are written out term by term."""
    x, v, f_int, f_ext, f_bulk = state.x, state.v, state.f_int, state.f_ext, state.f_bulk
    damping = control.damping
    beta = damping.beta
    steps = 0
    dt_seen = np.inf
    while t < t_stop:
        _zero(f_int)
        _zero(f_bulk)
        dte, w_int, w_hg, p_bulk = np.inf, 0.0, 0.0, 0.0
        for term in internal.terms:
            if term.size > 0:
                dt_term, w_term, hg_term, p_term, bad = term.kernel(x, v, term.data, internal.material, f_int)
                if bad >= 0:
                    return t, dt_prev, steps, term.failure, term.first + bad, dt_seen
                dte = min(dte, dt_term)
                w_int += w_term
                w_hg += hg_term
                p_bulk += p_term
                if term.bulk_force.shape[0] > 0:
                    _accumulate(f_bulk, term.bulk_force)
        dt_stable = _stable_step(dte, beta)
        if control.dt_user > 0.0:
            if control.dt_user > dt_stable:
                return t, dt_prev, steps, _STEP_TOO_LARGE, 0, dt_stable
            dt = control.dt_user
        else:
            dt = control.tssfac * dt_stable
        dt_seen = min(dt_seen, dt)
        _zero(f_ext)
        for term in external:
            if term.size > 0:
                term.kernel(t, x, v, term.data, f_ext)
        if frame.nodes.shape[0] > 0:
            prescribed_rotation(frame.nodes, nodes.X, x, nodes.v_pres, frame.center, frame.axis,
                                frame.omega * (t + dt), dt)
        Dt = 0.5 * (dt_prev + dt)
        beta_rate = beta / dt_prev if (beta > 0.0 and dt_prev > 0.0) else 0.0
        _trial_velocities(state, nodes, damping, frame, Dt, beta_rate)
        for term in external:
            if term.size > 0:
                term.impulse(state, nodes, damping, Dt, term.data, energy)
        if f_bulk.shape[0] > 0:
            p_bulk += _bulk_work(f_bulk, v, state.v_new)
        w_ext, w_damp, ke, mvb2 = _commit(state, nodes, damping, frame, Dt, dt, beta_rate)
        _record_energy(energy, w_ext, w_damp, Dt * p_bulk, ke, w_int, w_hg)
        if not (mvb2 < np.inf):              # also catches NaN
            return t, dt_prev, steps, _DIVERGED, steps, dt_seen
        t += dt
        dt_prev = dt
        steps += 1
    return t, dt_prev, steps, _OK, 0, dt_seen


@functools.cache
def _advance_numba(internal_kernels, external_kernels):
    """:func:`_advance` compiled by numba for internal terms with the kernels
    ``internal_kernels`` and external terms with the (kernel, impulse) pairs
    ``external_kernels``, in that order: its loops over the terms written out and each
    term's functions called by name (:func:`ccedi.fea.solvers.force_terms.unroll_terms`),
    so that the terms it is called with carry None in their place (:func:`_compiled_terms`)
    and numba caches it on disk. One dispatcher per set of kernels; every model of a
    backend has the same (a kind it lacks has size 0), so one per process, loaded from
    the cache after the first run on a machine. The cache entry is named after the
    kernels (a different set is a different entry)."""
    internal = tuple({"kernel": kernel} for kernel in internal_kernels)
    external = tuple({"kernel": kernel, "impulse": impulse} for kernel, impulse in external_kernels)
    names = [f"{f.__module__}.{f.__qualname__}" for f in (*internal_kernels, *(f for pair in external_kernels
                                                                               for f in pair))]
    tag = hashlib.sha1("|".join(names).encode()).hexdigest()[:12]
    written = unroll_terms(_advance, {"internal.terms": len(internal), "external": len(external)},
                           functions={"internal.terms": internal, "external": external}, name=f"_advance_{tag}")
    return nb.njit(cache=True, fastmath=FASTMATH)(written)


def _load_parallel_kernels(internal, x):
    """Call once, on its (possibly empty) data, every internal term's kernel that numba
    compiled with ``parallel=True`` (the hexahedra's), so that its code is loaded in this
    process: the step loop loaded from numba's cache calls into it, and in a process that
    had not run it (a tetrahedral finger) the call jumped to address 0 (a segfault)."""
    for term in internal.terms:
        if getattr(term.kernel, "targetoptions", {}).get("parallel"):
            term.kernel(x, np.zeros_like(x), term.data, internal.material, np.zeros_like(x))


def _compiled_terms(internal, external):
    """The terms as the compiled step loop takes them: the kernels replaced by None (it
    calls them by name, :func:`_advance_numba`)."""
    return (internal._replace(terms=tuple(term._replace(kernel=None) for term in internal.terms)),
            tuple(term._replace(kernel=None, impulse=None) for term in external))


def compiled_entry(dispatcher, *args):
    """The compiled overload of a numba ``dispatcher`` for the types of ``args``, compiled
    first if needed, to be called with arguments of those types.

    Calling the dispatcher types every argument first: for the step's groups (about a
    hundred arrays in named tuples) that costs ~70 us a call, as much as a hundred SM-A
    steps, and a run calls once per output. The overload's entry point skips it (~6 us).

    Parameters
    ----------
    dispatcher : numba.core.registry.CPUDispatcher
        An ``njit`` function.
    *args
        Arguments whose types select the overload.

    Returns
    -------
    callable
        The overload's entry point (the dispatcher itself if numba files it under other
        types than the arguments').
    """
    key = tuple(dispatcher.typeof_pyval(a) for a in args)
    if key not in dispatcher.overloads:
        dispatcher.compile(key)
    overload = dispatcher.overloads.get(key)
    return dispatcher if overload is None else overload.entry_point


@dataclass
class RunResult:
    """Output of :func:`run`.

    Parameters
    ----------
    history : pandas.DataFrame
        One row per output time, columns with units in their names (``time_s``,
        ``tip_ux_m`` ..., ``reaction_x_N`` ..., ``max_von_mises_Pa``,
        ``max_log_strain`` [-] (largest principal logarithmic strain of the solid
        elements, NaN without them), the energy terms [J], :data:`CONTACT_COLUMNS` with
        contact, and the output hook's columns).
    summary : dict
        Run statistics: ``nodes``, ``elements``, ``dt_initial_s``, ``dt_min_s``,
        ``steps``, ``t_end_s``, ``t_final_s``, ``wall_time_s``, ``backend``, ``threads``,
        ``alpha_per_s``, ``beta_s``, ``ns_per_element_cycle``, and the validity checks
        of :func:`ccedi.fea.solvers.validity.run_checks`: ``energy_balance_error``,
        ``hourglass_energy_fraction``, ``max_log_strain`` and ``warnings`` (list of str,
        empty for a healthy run).
    x : (n_nodes, 3) ndarray
        Final nodal positions [m], at ``summary["t_final_s"]``.
    v : (n_nodes, 3) ndarray
        Final half-step velocities [m/s].
    snapshots : list of (float, ndarray), optional
        ``(time_s, positions (n_nodes, 3) [m])`` every ``snapshot_every`` outputs;
        empty by default.
    """

    history: pd.DataFrame
    summary: dict
    x: np.ndarray
    v: np.ndarray
    snapshots: list = field(default_factory=list)


def max_von_mises(model, x):
    """Largest von Mises stress of a model at nodal positions ``x``.

    Parameters
    ----------
    model : Model
        The model (solid elements and rods).
    x : ndarray, shape (n, 3)
        Nodal positions [m].

    Returns
    -------
    float
        The larger of the solid elements' largest neo-Hookean Cauchy von Mises stress
        (:func:`ccedi.fea.material.max_von_mises_of`) and the rods' normal stress bound
        (:func:`ccedi.fea.elements.rod.rod_max_stress`) [Pa].
    """
    return _stress_and_strain(model, x)[0]


def _stress_and_strain(model, x):
    """(:func:`max_von_mises` [Pa], largest principal log strain of the solid elements
    [-], NaN without them) from one evaluation of the deformation gradients (of every
    hexahedron and every tetrahedron's integration points)."""
    sigma = rod_max_stress(x, model.rod_arrays)
    strain = np.nan
    if model.mesh.n_elements:
        g = model.geometry
        hex_grad = (g.b / g.volume[:, None, None])[:, None]
        F = np.concatenate([deformation_gradients_numba(x, model.mesh.hexes, hex_grad).reshape(-1, 3, 3),
                            deformation_gradients_numba(x, model.tet4.tets, model.tet4.grad[:, None]).reshape(-1, 3, 3),
                            deformation_gradients_numba(x, model.tet10.tets, model.tet10.grad).reshape(-1, 3, 3)])
        sigma = max(sigma, max_von_mises_of(F, model.material.mu, model.material.lam))
        strain = max_log_strain(F)
    return sigma, strain


def rod_time_step(model):
    """Smallest critical step of the rod elements, see :mod:`ccedi.fea.elements.rod`.

    Parameters
    ----------
    model : Model
        The model; its ``rod_arrays`` give the segment and hinge critical steps.

    Returns
    -------
    float
        min over segments and hinges of their critical steps [s] (inf without rods).
    """
    r = model.rod_arrays
    return float(min(np.min(r.segment_time_step, initial=np.inf), np.min(r.hinge_time_step, initial=np.inf)))


def critical_time_step(model, x=None, v=None):
    """Smallest critical step of the model, before the TSSFAC scale factor.

    ``min(min_e dt_e, rod step)``: the smallest stable step the model's internal force
    terms return (the run's terms, :mod:`ccedi.fea.solvers.force_terms`), for the solid
    elements paper Eq. (6), ``dt_e = Le / (Q + sqrt(Q^2 + c^2))`` (Q from the bulk
    viscosity, zero at rest; Le of :mod:`ccedi.fea.elements.hex8`,
    :mod:`ccedi.fea.elements.tet4`, :mod:`ccedi.fea.elements.tet10`).

    Parameters
    ----------
    model : Model
        The model.
    x : (n_nodes, 3) ndarray, optional
        Nodal positions [m]. Default: the reference positions.
    v : (n_nodes, 3) ndarray, optional
        Nodal velocities [m/s] (enter the bulk viscosity). Default: zero.

    Returns
    -------
    float
        Critical time step [s].

    Raises
    ------
    SolverError
        If an element is inverted (J <= 0) at ``x``.
    """
    x = model.mesh.nodes if x is None else x
    v = np.zeros_like(x) if v is None else v
    f = np.zeros_like(x)
    internal = _internal_forces(model, "numba")
    dt = np.inf
    for term in internal.terms:
        if term.size == 0:
            continue
        dt_term, *_, bad = term.kernel(x, v, term.data, internal.material, f)
        if bad >= 0 and term.failure == _INVERTED:
            raise SolverError(f"{element_name(model.mesh, term.first + bad)} is inverted (J <= 0)")
        dt = min(dt, dt_term)
    return dt


def element_stable_steps(model):
    """Stable step of every solid element at rest, ``dt_e = Le / c`` [s].

    ``c = sqrt((lambda + 2 mu) / rho)`` and the characteristic length Le of each element
    type (:func:`ccedi.fea.elements.hex8.characteristic_length`, the tetrahedra's
    ``kappa_e`` x minimum altitude, whose kappa_e carry the element's own mass, scaled
    or not); the smallest is the step before TSSFAC as :func:`critical_time_step` finds
    it at rest (the tetrahedra's exactly, the hexahedra's within about 1 %: 4.90 against
    4.85 us on SM-A).

    Parameters
    ----------
    model : Model
        A model with solid elements.

    Returns
    -------
    numpy.ndarray
        (n_elements,) [s], over the hexahedra, then the 4-node, then the 10-node
        tetrahedra (:func:`element_name`'s numbering).
    """
    return _element_lengths(model)[0] / _wave_speed(model)


def _wave_speed(model):
    m = model.material
    return np.sqrt((m.lam + 2.0 * m.mu) / m.rho)


def _element_lengths(model):
    """(Le, centroid) of every solid element at rest, in :func:`element_name`'s order [m]."""
    mesh, X = model.mesh, model.mesh.nodes
    lengths, centroids = [], []
    if len(mesh.hexes):
        lengths.append(hex_characteristic_length(X[mesh.hexes], element_geometry(X, mesh.hexes).volume))
        centroids.append(X[mesh.hexes].mean(axis=1))
    if len(mesh.tets4):
        lengths.append(model.tet4.length_factor * min_altitude(X[mesh.tets4]))
        centroids.append(X[mesh.tets4].mean(axis=1))
    if len(mesh.tets10):
        lengths.append(tet10_characteristic_length(X, model.tet10))
        centroids.append(X[mesh.tets10[:, :4]].mean(axis=1))
    return np.concatenate(lengths), np.concatenate(centroids)


def limiting_element(model):
    """The solid element that sets the stable step at rest, its size and where it is
    (:func:`element_stable_steps`).

    Parameters
    ----------
    model : Model
        A model with solid elements.

    Returns
    -------
    dict
        ``element`` (its name, :func:`element_name`), ``index`` (over all solid
        elements), ``dt_s`` [s], ``length_m`` (its Le) [m], ``median_length_m`` (of all
        elements) [m], ``centroid_m`` (3,) [m].
    """
    Le, centroids = _element_lengths(model)
    k = int(np.argmin(Le))
    return {"element": element_name(model.mesh, k), "index": k, "dt_s": float(Le[k] / _wave_speed(model)),
            "length_m": float(Le[k]), "median_length_m": float(np.median(Le)), "centroid_m": centroids[k]}


SLIVER_RATIO = 0.25
"""An element whose characteristic length is below this fraction of the mesh's median
sets a step that much shorter than the mesh needs (:func:`sliver_warnings`)."""


def sliver_warnings(model, e=None):
    """A validity message when one small element sets the whole run's step: the
    characteristic length of the element that sets it is below :data:`SLIVER_RATIO` of
    the median (a sliver where a hole meets the surface, say), with where it is.

    Parameters
    ----------
    model : Model
    e : dict, optional
        The model's :func:`limiting_element` when already found.

    Returns
    -------
    list of str
        Empty, or one message.
    """
    if model.mesh.n_elements == 0:
        return []
    e = e or limiting_element(model)
    if e["length_m"] >= SLIVER_RATIO * e["median_length_m"]:
        return []
    return [f"{_step_setter(model, e)}: the stable step is {e['median_length_m'] / e['length_m']:.3g} times shorter than "
            "the mesh's typical element needs; remesh with a minimum element size there (Gmsh: "
            "Mesh.CharacteristicLengthMin, or optimise the mesh) to make every run that much faster, or scale "
            "the small elements' mass (ccedi.fea.solvers.mass_scaling.mass_scaled)"]


def _step_setter(model, e=None):
    """``"the step is set by tet4 element 12 at (1, 2, 3) mm, 0.3 mm across (median 4 mm)"``;
    ``e``: the model's :func:`limiting_element` when already found."""
    if model.mesh.n_elements == 0:
        return "the rods set the step"
    e = e or limiting_element(model)
    where = ", ".join(f"{1e3 * c:.4g}" for c in e["centroid_m"])
    return (f"the step is set by {e['element']} at ({where}) mm, {1e3 * e['length_m']:.3g} mm across "
            f"(median {1e3 * e['median_length_m']:.3g} mm)")


def _initial_state(name, value, shape):
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a numeric array of shape {shape}") from None
    if a.shape != shape or not np.all(np.isfinite(a)):
        raise InputError(f"{name} must be finite with shape {shape}, got shape {a.shape}")
    return a


def _initial_energy(model, x, v, internal):
    """Kinetic plus stored (strain, hourglass, rod) energy [J] of the initial state x, v
    (v already zero on the constrained nodes), from the run's own force terms
    ``internal`` (:data:`InternalForces`, compiled or numpy reference); 0 for the stored
    part when an element fails at x (the step loop then stops at step 0)."""
    f = np.zeros_like(x)
    w_int = w_hg = 0.0
    failed = False
    for term in internal.terms:
        if term.size == 0:
            continue
        _, w_term, hg_term, _, bad = term.kernel(x, v, term.data, internal.material, f)
        w_int += w_term
        w_hg += hg_term
        failed = failed or bad >= 0
    stored = w_int + w_hg if not failed else 0.0
    return 0.5 * float(np.sum(model.mass[:, None] * v * v)) + stored


def _contact_group(model, dt_cfl):
    """The model's contact as a :data:`ContactGroup` (no slave nodes when it has none)."""
    n = model.mesh.n_nodes
    c = model.contact
    if c is None:
        kind, params, nodes, k, c_n, mu = PLANE, np.zeros(8), np.zeros(0, np.int64), np.zeros(0), np.zeros(0), 0.0
    else:
        kind, params = c.surface.params()
        nodes = np.asarray(c.nodes, dtype=np.int64)
        k = penalty_stiffness(model.mass[nodes], dt_cfl) if c.stiffness is None else np.asarray(c.stiffness, float)
        c_n = contact_damping(k, model.mass[nodes], c.surface.damping_ratio)
        mu = float(c.surface.mu)
    return ContactGroup(nodes, k, c_n, kind, params, mu, np.zeros((n, 3)), np.zeros(n), np.zeros(8))


TERM_KERNELS = {
    "numba": (hex_term, tet4_term, tet10_term, rod_term, contact_term),
    "numpy": (hex_term_numpy, tet4_term_numpy, tet10_term_numpy, rod_term_numpy, contact_term_numpy),
}
"""The force-term kernels of each backend (:mod:`ccedi.fea.solvers.force_terms`):
hexahedra, 4-node and 10-node tetrahedra, rods, contact."""


def _numbered(terms):
    """:data:`ForceTerm` s from ``(kernel, data, size, failure, bulk_force)``: each term's
    ``first`` is the count of the elements of the earlier terms that fail with the same
    status (the solid elements are numbered through, the rod hinges on their own)."""
    counts, numbered = {}, []
    for kernel, data, size, failure, bulk_force in terms:
        numbered.append(ForceTerm(kernel, data, size, counts.get(failure, 0), failure, bulk_force))
        counts[failure] = counts.get(failure, 0) + size
    return tuple(numbered)


def _internal_forces(model, backend):
    """The model's internal force terms with the kernels of ``backend`` ("numba" or
    "numpy"): hexahedra, 4-node, 10-node tetrahedra, rods, always all four (a kind the
    model lacks has size 0, and the step skips it), so that every model gives the
    compiled loop the same types and it compiles once per process. A new element kind is
    one more term here (its kernel in :data:`TERM_KERNELS`)."""
    hexes, tets4, tets10, rods = TERM_KERNELS[backend][:4]
    none = np.zeros((0, 3))
    ra = model.rod_arrays
    rod_group = RodGroup(ra.segments, ra.rest_length, ra.axial_stiffness, ra.hinges, ra.bending_stiffness,
                         rod_time_step(model))
    terms = _numbered((
        (hexes, model.hexahedra, len(model.hexahedra.hexes), _INVERTED, none),
        (tets4, model.tet4, len(model.tet4.tets), _INVERTED, model.tet4.bulk_force if len(model.tet4.tets) else none),
        (tets10, model.tet10, len(model.tet10.tets), _INVERTED,
         model.tet10.bulk_force if len(model.tet10.tets) else none),
        (rods, rod_group, len(ra.segments), _FOLDED, none),
    ))
    return InternalForces(terms, SolidMaterial(*model.solid_constants))


def _external_forces(model, contact, backend):
    """The model's external force terms with the kernels of ``backend``: the force pulses
    and the contact ``contact`` (a :data:`ContactGroup`, no slave nodes without contact)
    with its friction, always both (size 0 when the model has none)."""
    loads = pulse_loads(model.pulses)
    return (ExternalTerm(pulse_forces, no_impulse, loads, len(loads.nodes)),
            ExternalTerm(TERM_KERNELS[backend][4], friction_impulse, contact, len(contact.nodes)))


def _step_data(model, x, v, dt_user, tssfac, contact, backend="numba"):
    """The groups the step loop takes, for ``model`` starting from x, v.

    Parameters
    ----------
    model : Model
        The model.
    x, v : ndarray, shape (n, 3)
        Initial positions [m] and velocities [m/s]; used in place as the state.
    dt_user : float
        Fixed step [s], 0.0 for the CFL-controlled step.
    tssfac : float
        Scale factor of the CFL step [-].
    contact : ContactGroup
        The model's contact (:func:`_contact_group`), whose record the run reads.
    backend : {"numba", "numpy"}, optional
        Whose force kernels the terms take (:data:`TERM_KERNELS`).

    Returns
    -------
    tuple
        (control, state, nodes, internal, external, frame), as :func:`_advance` takes them
        after its clock.
    """
    mesh = model.mesh
    X = mesh.nodes
    free = np.ones(mesh.n_nodes)
    free[model.fixed_nodes] = 0.0
    rot = model.rotating
    if rot is not None:
        free[rot.nodes] = 0.0
        frame = RotatingFrame(rot.nodes, rot.center_m, rot.axis, float(rot.omega_rad_s))
    else:
        frame = RotatingFrame(np.zeros(0, np.int64), np.zeros(3), np.array([0.0, 0.0, 1.0]), 0.0)
    v *= free[:, None]
    internal = _internal_forces(model, backend)
    bulk = any(len(term.bulk_force) for term in internal.terms)
    state = State(x, v, *(np.zeros_like(X) for _ in range(5)), np.zeros_like(X) if bulk else np.zeros((0, 3)))
    mass3 = np.repeat(model.mass[:, None], 3, axis=1)
    inv_mass = np.divide(1.0, mass3, out=np.zeros_like(mass3), where=mass3 > 0.0)     # massless: constrained
    nodes = Nodes(X, model.mass, mass3, inv_mass, free, np.flatnonzero(free == 0.0), np.zeros_like(X))
    control = StepControl(dt_user, tssfac, Damping(model.alpha, model.beta, model.damping == "relative"))
    return control, state, nodes, internal, _external_forces(model, contact, backend), frame


CONTACT_COLUMNS = ["contact_force_x_N", "contact_force_y_N", "contact_force_z_N", "penalty_energy_J",
                   "max_penetration_m", "contact_nodes", "contact_point_x_m", "contact_point_y_m",
                   "normal_contact_work_J", "friction_work_J"]
"""History columns added when the model has contact: force on the rigid surface [N],
stored penalty energy [J], deepest penetration [m], nodes in contact, force-weighted
contact point [m], work of the normal and friction contact forces on the body [J]."""


ELEMENT_CYCLE_S = {"hex8": 3e-7, "tet4": 4e-7, "tet10": 1.6e-6}
"""About how long one element takes per step on one core [s] (``benchmarks/fea_speed.json``,
``benchmarks/tet_speed.json``: 168-427 ns hex8, 350 ns tet4, 1592 ns tet10 on the 2-core
AMD VM), for the expected wall time :func:`run` states before it starts."""


BUDGET_ESTIMATE_MARGIN = 1.05
"""A run is refused from the at-rest estimate of its step (:func:`limiting_element`,
within about 1 % of :func:`critical_time_step` for hexahedra) only when it exceeds the
budget by this factor; closer calls wait for the exact step."""


def _check_budget(model, t_end_s, dt_s, budget, limiting, margin=1.0):
    """The expected step count ``t_end_s / dt_s``; InputError when it exceeds ``margin``
    x ``budget``, naming the steps, the expected time and the element that sets the step
    (``limiting``, the model's :func:`limiting_element`, None without solid elements)."""
    n_expected = t_end_s / dt_s
    if n_expected > margin * budget:
        mesh = model.mesh
        raise InputError(f"t_end_s = {t_end_s:g} s at the stable step {dt_s:.3g} s is about {n_expected:.3g} steps, "
                         f"beyond the budget of {budget:.3g} (about "
                         f"{_duration(expected_wall_time_s(mesh, n_expected))} for {mesh.n_elements} elements on one "
                         f"core); {_step_setter(model, limiting)}; check E and rho, coarsen the mesh there, or raise the budget "
                         f"(--max-steps, {STEPS_ENV})")
    return n_expected


def expected_wall_time_s(mesh, steps):
    """About how long ``steps`` steps of ``mesh`` take on one core [s] (:data:`ELEMENT_CYCLE_S`).

    Parameters
    ----------
    mesh : Mesh
    steps : float

    Returns
    -------
    float
    """
    per_step = (len(mesh.hexes) * ELEMENT_CYCLE_S["hex8"] + len(mesh.tets4) * ELEMENT_CYCLE_S["tet4"]
                + len(mesh.tets10) * ELEMENT_CYCLE_S["tet10"])
    return steps * per_step


def _duration(seconds):
    """``"3.2 min"``-style duration."""
    for unit, size in (("d", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if seconds >= size:
            return f"{seconds / size:.2g} {unit}"
    return f"{seconds:.2g} s"


RunPlan = namedtuple("RunPlan", "t_end_s n_outputs dt_user tssfac limiting dt_cfl dt_first n_expected")
RunPlan.__doc__ = """A run's checked arguments and its step, worked out before it starts (:func:`run_plan`).

Attributes
----------
t_end_s : float
    End time [s].
n_outputs : int
    Output rows.
dt_user : float
    Fixed step [s]; 0.0 for the CFL-controlled step.
tssfac : float
    Scale factor of the CFL step [-].
limiting : dict or None
    The element that sets the step (:func:`limiting_element`); None without solid elements.
dt_cfl : float
    Critical step of the model at rest [s].
dt_first : float
    The first step [s].
n_expected : float
    Expected step count.
"""


def run_plan(model, t_end_s, *, n_outputs, dt_s, max_steps):
    """Check a run's arguments and work out its step (:func:`run`'s parameters).

    Parameters
    ----------
    model : Model
        The model.
    t_end_s : float
        End time [s].
    n_outputs : int
        Output rows.
    dt_s : float or None
        Fixed step [s], or None for the CFL-controlled step.
    max_steps : int or None
        Step budget.

    Returns
    -------
    RunPlan

    Raises
    ------
    InputError
        An argument is out of range, ``dt_s`` exceeds the CFL limit, or the run would take
        more steps than its budget.
    """
    t_end_s = require_finite_positive("t_end_s (end time, s)", t_end_s)
    n_outputs = check_outputs(n_outputs)
    mesh = model.mesh
    dt_user = 0.0 if dt_s is None else require_finite_positive("dt_s (time step, s)", dt_s)
    budget = step_budget(max_steps)
    tssfac = TSSFAC * (STEP_SHRINK if model.contact is not None else 1.0)
    limiting = limiting_element(model) if mesh.n_elements else None
    if not dt_user and limiting:                    # refused before the kernels compile (tens of seconds, cold)
        _check_budget(model, t_end_s, tssfac * min(limiting["dt_s"], rod_time_step(model)), budget, limiting,
                      margin=BUDGET_ESTIMATE_MARGIN)
    dt_cfl = critical_time_step(model)
    if dt_user > dt_cfl:
        raise InputError(f"dt_s = {dt_user:.4g} s exceeds the CFL limit {dt_cfl:.4g} s "
                         f"(paper Eq. 6); use dt_s <= {TSSFAC * dt_cfl:.4g} s or leave it unset")
    dt_first = dt_user if dt_user else tssfac * dt_cfl
    n_expected = _check_budget(model, t_end_s, dt_first, budget, limiting)
    return RunPlan(t_end_s, n_outputs, dt_user, tssfac, limiting, dt_cfl, dt_first, n_expected)


def check_status(mesh, status, info, *, t, steps, dt_seen, dt_user):
    """Raise the step loop's failure, if any, as a :class:`SolverError` naming what failed.

    Parameters
    ----------
    mesh : Mesh
        The model's mesh (for the element's name).
    status : int
        The step loop's status.
    info : int
        The failed element or rod hinge.
    t : float
        Time reached [s].
    steps : int
        Steps taken.
    dt_seen : float
        Smallest step (the stable step, for a fixed step that got too large) [s].
    dt_user : float
        The fixed step [s] (0.0 for the CFL step).

    Raises
    ------
    SolverError
        An element inverted, a rod hinge folded, the solution diverged or the fixed step
        exceeds the stable step.
    """
    if status == _INVERTED:
        raise SolverError(f"{element_name(mesh, info)} inverted (J <= 0) at t = {t:.6g} s, step {steps}: "
                          "the mesh is too coarse for the deformation there; refine it")
    if status == _FOLDED:
        raise SolverError(f"rod hinge {info} folded back on itself (turning angle >= 180 deg) "
                          f"at t = {t:.6g} s, step {steps}")
    if status == _DIVERGED:
        raise SolverError(f"solution diverged (non-finite velocity) at step {steps + 1}, t = {t:.6g} s")
    if status == _STEP_TOO_LARGE:
        raise SolverError(f"dt_s = {dt_user:.4g} s exceeds the current stable step {dt_seen:.4g} s "
                          f"at step {steps}, t = {t:.6g} s (the mesh deformed)")


OutputPoints = namedtuple("OutputPoints", "tip tip_weights reaction")
OutputPoints.__doc__ = """Where a run's history is read (:func:`output_points`).

Attributes
----------
tip : (k,) int ndarray
    The tip nodes.
tip_weights : (k,) ndarray
    Their area weights [-] (sum 1).
reaction : (r,) int ndarray
    The nodes whose support reactions are summed.
"""


def output_points(mesh, tip_set, reaction_set):
    """The tip nodes with their weights and the reaction nodes of a run's history.

    Parameters
    ----------
    mesh : Mesh
    tip_set, reaction_set : str
        Node set names.

    Returns
    -------
    OutputPoints
    """
    tip = mesh.node_sets[tip_set]
    return OutputPoints(tip, face_node_weights(mesh, tip) if len(tip) > 1 else np.ones(1), mesh.node_sets[reaction_set])


def output_row(model, points, *, t_out, t, x, v, reaction, energy, contact):
    """One history row at the output time ``t_out``, from the state at ``t`` (the end of
    the step that reached it).

    Positions (and the displacement and stress derived from them) are moved back to
    t_out, exactly, since central differences move each node linearly over a step;
    reactions and energies are the step's.

    Parameters
    ----------
    model : Model
    points : OutputPoints
    t_out, t : float
        Output time and the state's time [s], ``t - dt < t_out <= t``.
    x, v : (n, 3) ndarray
        Positions [m] and half-step velocities [m/s] at t.
    reaction : (n, 3) ndarray
        Support reactions [N].
    energy : (9,) ndarray
        The energy record [J].
    contact : ContactGroup
        The run's contact (its record is read when the model has contact).

    Returns
    -------
    row : tuple
        The values of the history's columns (:data:`HISTORY_COLUMNS`, then
        :data:`CONTACT_COLUMNS` with contact).
    x_out : (n, 3) ndarray
        Positions at t_out [m].
    """
    X = model.mesh.nodes
    x_out = x - (t - t_out) * v
    u_tip = points.tip_weights @ (x_out[points.tip] - X[points.tip])
    r = reaction[points.reaction].sum(axis=0)
    row = (t_out, *u_tip, *r, *_stress_and_strain(model, x_out), *energy[:E_PENALTY])
    if model.contact is not None:
        out = contact.out
        row += (*out[:3], energy[E_PENALTY], *out[4:], energy[W_NORMAL], energy[W_FRICTION])
    return row, x_out


HISTORY_COLUMNS = ["time_s", "tip_ux_m", "tip_uy_m", "tip_uz_m", "reaction_x_N", "reaction_y_N", "reaction_z_N",
                   "max_von_mises_Pa", "max_log_strain", "external_work_J", "damping_energy_J",
                   "bulk_viscosity_energy_J", "kinetic_energy_J", "internal_energy_J", "hourglass_energy_J"]
"""The columns every run's history has: time [s], tip displacement [m], support reaction
[N], largest von Mises stress [Pa] and log strain [-], and the energy record [J]."""


def run_record(model, plan, rows, *, extra_columns, energy_0, t_final, steps, dt_min, wall, backend, threads):
    """A run's history and summary, with its validity checks (warnings issued once).

    Parameters
    ----------
    model : Model
    plan : RunPlan
    rows : list of tuple
        History rows (:func:`output_row`, then the output hook's values).
    extra_columns : list of str
        The output hook's column names.
    energy_0 : float
        Energy of the initial state [J].
    t_final : float
        Time reached [s].
    steps : int
        Steps taken.
    dt_min : float
        Smallest step [s].
    wall : float
        Wall time of the step loop [s].
    backend : str
        Whose kernels ran.
    threads : int
        Threads the run used.

    Returns
    -------
    history : pandas.DataFrame
    summary : dict
    """
    mesh = model.mesh
    cols = HISTORY_COLUMNS + (CONTACT_COLUMNS if model.contact is not None else []) + list(extra_columns)
    history = pd.DataFrame(rows, columns=cols)
    n_elements = mesh.n_elements + len(model.rod_arrays.segments)
    summary = {"nodes": mesh.n_nodes, "elements": n_elements, "dt_initial_s": plan.dt_first,
               "dt_min_s": float(dt_min), "steps": int(steps), "t_end_s": plan.t_end_s, "t_final_s": t_final,
               "wall_time_s": wall, "backend": backend, "threads": threads, "alpha_per_s": model.alpha,
               "beta_s": model.beta,
               "ns_per_element_cycle": 1e9 * wall / max(1, steps * n_elements)}
    summary.update(run_checks(history, energy_0))
    summary["warnings"] += sliver_warnings(model, plan.limiting)
    issue(summary["warnings"], run_label(model.alpha, model.damping))
    return history, summary


def run(model: Model, t_end_s, *, n_outputs=400, dt_s=None, backend="numba", tip_set="tip",
        reaction_set="root", snapshot_every=0, x0=None, v0=None, progress=False, output_hook=None, threads=None,
        max_steps=None):
    """Integrate ``model`` with central differences from rest (or x0, v0) to ``t_end_s``.

    Solves ``M a + (alpha M + beta K) v + f_int(x) = f_ext`` with the update of the
    module docstring. Records ``n_outputs`` evenly spaced rows: tip displacement
    (area-weighted mean over ``tip_set``), reaction force summed over
    ``reaction_set``, max von Mises stress and the energy terms. Steps are never
    shortened to hit an output time: positions (and the displacement and stress derived
    from them) are interpolated to the output time, exactly, since central differences
    move nodes linearly within a step; energies and reactions are those of the step
    that reaches it (at most one step later). The final state ``x, v`` is at
    ``summary["t_final_s"]`` (>= t_end_s, by less than one step). After the run the
    validity checks of :mod:`ccedi.fea.solvers.validity` (energy balance, hourglass energy,
    strain) fill the summary; each warning is issued once as a
    :class:`ccedi.errors.ValidityWarning`.

    Parameters
    ----------
    model : Model
        The finite element model (mesh, material, supports, loads, contact, damping).
    t_end_s : float
        End time [s], > 0.
    n_outputs : int, optional
        Number of output rows, 1..:data:`ccedi.fea.solvers.budget.MAX_OUTPUTS`, at
        ``t_end_s k / n_outputs``. Default 400.
    dt_s : float, optional
        Fixed step [s], at most the CFL limit. Default None: CFL-controlled,
        TSSFAC x min dt_e recomputed every step (times 0.9 more when the model has
        contact, see :mod:`ccedi.fea.contact.penalty`).
    backend : {"numba", "numpy"}, optional
        ``"numba"`` (compiled, default) or ``"numpy"`` (pure-numpy reference, slow).
    tip_set : str, optional
        Node set whose area-weighted mean displacement is recorded. Default ``"tip"``.
    reaction_set : str, optional
        Node set whose summed support reaction is recorded. Default ``"root"``.
    snapshot_every : int, optional
        Keep the positions every this many outputs in ``snapshots`` (0: none, default).
    x0 : (n_nodes, 3) array_like, optional
        Initial positions [m]. Default: the reference positions.
    v0 : (n_nodes, 3) array_like, optional
        Initial velocities [m/s] (zeroed on constrained nodes). Default: zero.
    progress : bool, optional
        Show a progress bar (tqdm) over the output times, headed by the run's expected
        step count and wall time. Default False.
    output_hook : callable, optional
        ``hook(t_out, x_out, f_ext) -> dict`` called at every output with the
        interpolated positions [m] and the external nodal forces of the last step
        (pulses and contact) [N]; its dict values become extra history columns.
    threads : int, optional
        Threads of the compiled hexahedron kernel (:func:`ccedi.threads.thread_count`; default: the
        free cores). The results are the same bits for any count.
    max_steps : int, optional
        Step budget (:func:`ccedi.fea.solvers.budget.step_budget`; default ``CCEDI_MAX_STEPS`` or
        :data:`ccedi.fea.solvers.budget.MAX_STEPS`): a run expected to take more steps
        (``t_end_s`` over the first stable step) is refused before it starts.

    Returns
    -------
    RunResult
        History, summary, final state and snapshots.

    Raises
    ------
    InputError
        If ``model`` is not a :class:`ccedi.fea.model.Model`, ``t_end_s`` or ``dt_s`` is
        not finite and positive, ``n_outputs`` is not an integer in 1..MAX_OUTPUTS, ``backend`` is
        unknown, ``dt_s`` exceeds the CFL limit, ``x0``/``v0`` are not finite arrays
        of the mesh's node shape, ``threads`` is out of range, or the run would take more
        steps than its budget (:func:`step_budget`; the message gives the step count, the
        stable step and the expected wall time).
    SolverError
        If an element inverts, a rod hinge folds back on itself, the solution diverges
        or the mesh deforms so that a fixed ``dt_s`` exceeds the stable step.
    """
    if not isinstance(model, Model):
        raise InputError("model must be a fea.model.Model")
    if backend not in ("numba", "numpy"):
        raise InputError(f"backend must be 'numba' or 'numpy', got {backend!r}")
    n_threads = thread_count(threads)
    plan = run_plan(model, t_end_s, n_outputs=n_outputs, dt_s=dt_s, max_steps=max_steps)
    t_end_s, n_outputs, dt_user, n_expected = plan.t_end_s, plan.n_outputs, plan.dt_user, plan.n_expected
    mesh = model.mesh
    X = mesh.nodes
    x = X.copy() if x0 is None else _initial_state("x0 (initial positions, m)", x0, X.shape)
    v = np.zeros_like(X) if v0 is None else _initial_state("v0 (initial velocities, m/s)", v0, X.shape)
    contact = _contact_group(model, plan.dt_cfl)
    groups = _step_data(model, x, v, dt_user, plan.tssfac, contact, backend)
    _, state, _, internal, external, _ = groups
    outputs = output_points(mesh, tip_set, reaction_set)
    energy = np.zeros(9)
    energy_0 = _initial_energy(model, x, v, internal)

    rows, snapshots = [], []
    t, dt_prev, steps, dt_min = 0.0, 0.0, 0, np.inf
    wall0 = _time.perf_counter()
    times = np.linspace(0.0, t_end_s, n_outputs + 1)[1:]
    if progress:
        times = progress_bar(times, desc=f"t_end {t_end_s:g} s, ~{n_expected:.3g} steps, "
                                         f"~{_duration(expected_wall_time_s(mesh, n_expected))}", unit="output")
    advance = _advance
    if backend == "numba":
        dispatcher = _advance_numba(tuple(term.kernel for term in internal.terms),
                                    tuple((term.kernel, term.impulse) for term in external))
        _load_parallel_kernels(internal, x)
        control, _, nodes, _, _, frame = groups
        groups = (control, state, nodes, *_compiled_terms(internal, external), frame)
        advance = compiled_entry(dispatcher, t, t_end_s, dt_prev, *groups, energy)
    threads_before = nb.get_num_threads()
    nb.set_num_threads(n_threads)
    try:
        for i_out, t_out in enumerate(times):
            t, dt_prev, n, status, info, dt_seen = advance(t, t_out, dt_prev, *groups, energy)
            steps += n
            dt_min = min(dt_min, dt_seen)
            check_status(mesh, status, info, t=t, steps=steps, dt_seen=dt_seen, dt_user=dt_user)
            row, x_out = output_row(model, outputs, t_out=t_out, t=t, x=x, v=v, reaction=state.reaction,
                                    energy=energy, contact=contact)
            if output_hook is not None:
                extra = output_hook(t_out, x_out, state.f_ext)
                row += tuple(extra.values())
            rows.append(row)
            if snapshot_every and (i_out + 1) % snapshot_every == 0:
                snapshots.append((t_out, x_out))
    finally:
        nb.set_num_threads(threads_before)
        if progress:
            times.close()       # before an error message is printed, so it starts a line of its own
    wall = _time.perf_counter() - wall0
    history, summary = run_record(model, plan, rows, extra_columns=list(extra) if output_hook is not None else [],
                                  energy_0=energy_0, t_final=t, steps=steps, dt_min=dt_min, wall=wall,
                                  backend=backend, threads=n_threads)
    return RunResult(history=history, summary=summary, x=x, v=v, snapshots=snapshots)

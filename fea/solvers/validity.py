"""Guards on the range of validity of a run: never an unflagged number.

A run whose results leave the range where the model means something either ends with a
:class:`ccedi.errors.SolverError` (the numbers mean nothing) or carries a warning: the
message is recorded in the run's summary (``warnings``, a list of str, empty for a
healthy run) and issued once as a :class:`ccedi.errors.ValidityWarning`, which the
command line prints on stderr (``ccedi <command>: warning: ...``); the numbers are still
written. The checks, one function each, with the thresholds below:

* energy balance error (:func:`energy_balance_error`) above
  :data:`ENERGY_BALANCE_TOLERANCE`: warning;
* hourglass energy over internal energy (:func:`hourglass_fraction`) above
  :data:`HOURGLASS_FRACTION_LIMIT`: warning;
* largest principal logarithmic strain of the solid elements (:func:`max_log_strain`,
  the history column ``max_log_strain``) above :data:`LOG_STRAIN_LIMIT`: warning;
* tip deflection under an impulse (:func:`tip_deflection_warnings`, full and reduced
  impulse models alike) above :data:`TIP_DEFLECTION_WARNING_FRACTION` of the length:
  warning; at :data:`TIP_DEFLECTION_ERROR_FRACTION` of the length or more: error.

Inverted elements, folded rods and non-finite numbers already stop the solver with a
:class:`ccedi.errors.SolverError` (:func:`ccedi.fea.solvers.explicit.run`).

There is no rotation guard. The hexahedron is total-Lagrangian with the neo-Hookean
stress of the full deformation gradient, and its hourglass displacements ``gamma . x``
are pulled back by the element's F^-1 before they meet the hourglass stiffness
(:mod:`ccedi.fea.elements.hex8`), so any rotation is exact; the finger on the drum turns by more than a radian by design. What large
rotations do invalidate is the linear modal model and the damping identification of an
impulse test, and the tip deflection guard is that check.

The solver (:func:`ccedi.fea.solvers.explicit.run`) and the impulse models issue the warnings
where they are found; :func:`ccedi.distributed.map_runs` carries those of runs on
Dask workers back to the caller.
"""
import math
import warnings

import numba as nb
import numpy as np

from ccedi.errors import SolverError, ValidityWarning
from ccedi.fea.elements.fastmath import FASTMATH

ENERGY_BALANCE_TOLERANCE = 0.02
"""Largest accepted energy balance error [-] (:func:`energy_balance_error`).

Belytschko, Liu & Moran, *Nonlinear Finite Elements for Continua and Structures* (2000),
sec. 6.2.3, ask of an explicit run ``|W_kin + W_int - W_ext| <= eps max(W_ext, W_int,
W_kin)`` with eps of the order of 1e-2; 2 % leaves room for the contact penalty. Healthy
runs of this solver stay far below it (measured: 0.017 % for the 4.5-in SM-A impulse at
alpha = 180 1/s, 0.0013 % for the drum contact at 180 1/s), so the check fires only on a
broken run (an unstable step, a contact that injects or absorbs energy)."""

HOURGLASS_FRACTION_LIMIT = 0.15
"""Largest accepted hourglass energy over internal energy [-] (:func:`hourglass_fraction`).

The LS-DYNA rule of thumb (LSTC support notes on hourglass control,
https://dynasupport.com/howtos/element/hourglass) is 10 % of the peak internal energy,
for hourglass energy that is pure error. ccedi's hourglass stiffness is physical (the
incompatible-modes element's, :mod:`ccedi.fea.elements.hex8`, Q_hg = 1): it carries the part of
the bending energy that varies linearly inside an element, 1/n^2 of it for n elements
through the thickness in pure bending, so part of it is real bending energy. Measured: a
nonlinear static 1 N tip load puts 7.0 % of the internal energy in it on SM-A (5 x 5
section) and 2.1 % on SM-B, the impulse runs at alpha = 180 1/s 8.0 % (4.5 in) and 8.4 %
(3 in). At 10 % a section a little coarser than SM-A's would be flagged although its
stabilisation is physical; the limit is half as much again, so it flags a section much
coarser than SM-A's, a point load or a small hourglass coefficient, where the one-point
elements' stabilisation, not the material, carries the response."""


LOG_STRAIN_LIMIT = 0.5
"""Largest accepted principal logarithmic (Hencky) strain magnitude [-] (:func:`max_log_strain`).

|ln lambda| = 0.5 is a stretch of 1.65 in tension or 0.61 in compression. The
compressible neo-Hookean law holds the paper's small-strain constants (E = 6.1 MPa),
while rubber softens with stretch: its uniaxial reduced stress (Mooney plot) is
``2 C1 + 2 C2 / lambda``, so with a typical Mooney-Rivlin ratio C2 / C1 = 0.5 the
neo-Hookean law overestimates the tensile stress by 8 % at a stretch of 1.3 and by 13 %
at 1.65. Beyond this strain the material law, not the finger, decides the numbers.
Healthy runs stay below it (measured: 0.011 for the 4.5-in impulse at alpha = 180 1/s,
0.32 where the finger wraps the object in the drum contact at 180 1/s)."""


TIP_DEFLECTION_WARNING_FRACTION = 0.30
"""Tip deflection under an impulse, as a fraction of the structure's length, above which
the run is flagged [-] (:func:`tip_deflection_warnings`).

The paper's damping identification and the modal reduced model are linear, small
deflection. For a cantilever under a tip load the elastica (Bisshopp & Drucker, Q. Appl.
Math. 3, 1945) gives a tip deflection of 0.30 L at P L^2 / EI = 1, where the linear
value is 10 % larger (0.33 L): beyond 0.3 L geometric nonlinearity changes the response
by more than 10 %."""

TIP_DEFLECTION_ERROR_FRACTION = 1.0
"""Tip deflection under an impulse, as a fraction of the structure's length, at which the
run is an error [-] (:func:`tip_deflection_warnings`).

A tip load cannot bend an inextensible cantilever as far as its length along the load
(the elastica's deflection tends to L as the load grows); a deflection of L or more
means the structure is stretched like a rope, or, for a linear model, that the linear
answer has no physical meaning."""


def energy_balance_error(history, initial_energy_J=0.0):
    """Largest energy balance error of a run, relative to the energies involved.

    With the solver's energies (:func:`ccedi.fea.solvers.explicit.run`) the balance is
    ``E0 + W_ext = KE + IE + HG + E_damping + E_bulk`` at every output, where ``W_ext``
    is the work of the loads, the supports (the turning drum) and the contact forces (so
    the penalty energy and the friction dissipation are in it, as LS-DYNA's sliding
    energy), and ``E0`` the energy of the initial state. The error is (Belytschko, Liu &
    Moran 2000, sec. 6.2.3)::

        max_t |E0 + W_ext - (KE + IE + HG + E_damping + E_bulk)|
        / max_t max(|E0 + W_ext|, KE, IE + HG + E_damping + E_bulk)

    Parameters
    ----------
    history : pandas.DataFrame
        A run's history with the columns ``external_work_J``, ``kinetic_energy_J``,
        ``internal_energy_J``, ``hourglass_energy_J``, ``damping_energy_J`` and
        ``bulk_viscosity_energy_J`` [J].
    initial_energy_J : float, optional
        Kinetic plus stored energy of the initial state [J].

    Returns
    -------
    float
        The relative error [-]; 0 when no energy is involved at all.
    """
    h = history
    supplied = initial_energy_J + h.external_work_J.to_numpy()
    absorbed = (h.internal_energy_J + h.hourglass_energy_J + h.damping_energy_J
                + h.bulk_viscosity_energy_J).to_numpy()
    kinetic = h.kinetic_energy_J.to_numpy()
    scale = max(np.abs(supplied).max(), kinetic.max(), absorbed.max())
    if not scale > 0.0:
        return 0.0
    return float(np.abs(supplied - kinetic - absorbed).max() / scale)


def hourglass_fraction(history):
    """Largest hourglass energy over largest internal (strain) energy of a run.

    Parameters
    ----------
    history : pandas.DataFrame
        A run's history with ``hourglass_energy_J`` and ``internal_energy_J`` [J].

    Returns
    -------
    float
        ``max_t HG / max_t IE`` [-]; 0 for a run that stores no energy.
    """
    ie = float(history.internal_energy_J.max())
    hg = float(history.hourglass_energy_J.max())
    return hg / ie if ie > 0.0 else (math.inf if hg > 0.0 else 0.0)


@nb.njit(cache=True, fastmath=FASTMATH)
def max_log_strain(F):
    """Largest principal logarithmic (Hencky) strain magnitude of deformation gradients.

    ``max_e max_i |ln lambda_i|`` with the principal stretches lambda_i, the square roots
    of the eigenvalues of ``C = F^T F`` (closed form for a symmetric 3x3, Smith 1961).

    Parameters
    ----------
    F : ndarray, shape (e, 3, 3)
        Deformation gradients [-] (det F > 0).

    Returns
    -------
    float
        The largest |ln lambda| [-] (0 for no element).
    """
    worst = 0.0
    for e in range(F.shape[0]):
        c00 = F[e, 0, 0] ** 2 + F[e, 1, 0] ** 2 + F[e, 2, 0] ** 2
        c11 = F[e, 0, 1] ** 2 + F[e, 1, 1] ** 2 + F[e, 2, 1] ** 2
        c22 = F[e, 0, 2] ** 2 + F[e, 1, 2] ** 2 + F[e, 2, 2] ** 2
        c01 = F[e, 0, 0] * F[e, 0, 1] + F[e, 1, 0] * F[e, 1, 1] + F[e, 2, 0] * F[e, 2, 1]
        c02 = F[e, 0, 0] * F[e, 0, 2] + F[e, 1, 0] * F[e, 1, 2] + F[e, 2, 0] * F[e, 2, 2]
        c12 = F[e, 0, 1] * F[e, 0, 2] + F[e, 1, 1] * F[e, 1, 2] + F[e, 2, 1] * F[e, 2, 2]
        q = (c00 + c11 + c22) / 3.0
        off = c01 * c01 + c02 * c02 + c12 * c12
        p = np.sqrt(((c00 - q) ** 2 + (c11 - q) ** 2 + (c22 - q) ** 2 + 2.0 * off) / 6.0)
        if p > 0.0:
            b00 = (c00 - q) / p
            b11 = (c11 - q) / p
            b22 = (c22 - q) / p
            b01 = c01 / p
            b02 = c02 / p
            b12 = c12 / p
            r = 0.5 * (b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02)
                       + b02 * (b01 * b12 - b11 * b02))
            phi = np.arccos(min(1.0, max(-1.0, r))) / 3.0
            largest = q + 2.0 * p * np.cos(phi)
            smallest = q + 2.0 * p * np.cos(phi + 2.0 * np.pi / 3.0)
        else:
            largest = q
            smallest = q
        worst = max(worst, 0.5 * abs(np.log(largest)), 0.5 * abs(np.log(smallest)))
    return worst


def run_checks(history, initial_energy_J=0.0):
    """The validity measures and warnings of an explicit run.

    Parameters
    ----------
    history : pandas.DataFrame
        The run's history (:func:`ccedi.fea.solvers.explicit.run`): the energy columns and
        ``max_log_strain``.
    initial_energy_J : float, optional
        Kinetic plus stored energy of the initial state [J].

    Returns
    -------
    dict
        ``energy_balance_error`` [-] (:func:`energy_balance_error`),
        ``hourglass_energy_fraction`` [-] (:func:`hourglass_fraction`),
        ``max_log_strain`` [-] (largest of the history column, None without solid
        elements) and ``warnings`` (list of str, one per exceeded threshold).
    """
    balance = energy_balance_error(history, initial_energy_J)
    hourglass = hourglass_fraction(history)
    strains = history.max_log_strain.to_numpy()
    strain = float(strains.max()) if not np.isnan(strains).all() else None
    out = []
    if balance > ENERGY_BALANCE_TOLERANCE:
        out.append(f"energy balance error {balance:.1%} exceeds {ENERGY_BALANCE_TOLERANCE:.0%}: the external work "
                   "and the initial energy do not match the kinetic, internal, hourglass, damping and bulk-viscosity "
                   "energies (an unstable step, or a contact injecting or absorbing energy)")
    if hourglass > HOURGLASS_FRACTION_LIMIT:
        out.append(f"hourglass energy is {hourglass:.0%} of the internal energy (limit "
                   f"{HOURGLASS_FRACTION_LIMIT:.0%}): the one-point elements' hourglass control carries much of the "
                   "deformation; refine the mesh or spread the loads")
    if strain is not None and strain > LOG_STRAIN_LIMIT:
        out.append(f"largest principal logarithmic strain {strain:.2f} exceeds {LOG_STRAIN_LIMIT:.2f} (stretch "
                   f"{math.exp(-strain):.2f} to {math.exp(strain):.2f}): beyond the strains for which the "
                   "neo-Hookean law fits rubber")
    return {"energy_balance_error": balance, "hourglass_energy_fraction": hourglass, "max_log_strain": strain,
            "warnings": out}


def tip_deflection_warnings(tip_uy_m, length_m):
    """The tip deflection check of an impulse test (full or reduced model).

    Parameters
    ----------
    tip_uy_m : array_like
        Tip displacement along the load over the run [m].
    length_m : float
        Length of the structure from the clamp to the tip [m].

    Returns
    -------
    list of str
        One warning when the largest |tip_uy_m| exceeds
        :data:`TIP_DEFLECTION_WARNING_FRACTION` of the length, else none.

    Raises
    ------
    SolverError
        When the largest |tip_uy_m| reaches :data:`TIP_DEFLECTION_ERROR_FRACTION` of the
        length, or is not finite.
    """
    deflection = float(np.max(np.abs(np.asarray(tip_uy_m, dtype=float))))
    ratio = deflection / length_m
    if not ratio < TIP_DEFLECTION_ERROR_FRACTION:
        raise SolverError(f"tip deflection {deflection:.4g} m is {ratio:.0%} of the length {length_m:.4g} m under an "
                          "impulse: a tip load cannot bend a cantilever that far, so the result means nothing "
                          "(reduce the force)")
    if ratio > TIP_DEFLECTION_WARNING_FRACTION:
        return [f"tip deflection {1e3 * deflection:.1f} mm is {ratio:.0%} of the length {1e3 * length_m:.1f} mm "
                f"(limit {TIP_DEFLECTION_WARNING_FRACTION:.0%}): beyond small deflection, where the linear modal "
                "model and the damping identification hold"]
    return []


def cantilever_length_m(mesh, root_set="root", tip_set="tip"):
    """Length of a cantilever: the distance between the centroids of its root and tip
    node sets in the reference configuration.

    Parameters
    ----------
    mesh : ccedi.fea.mesh.Mesh
        The mesh, with the two node sets.
    root_set, tip_set : str, optional
        Names of the clamped and the loaded node set.

    Returns
    -------
    float
        Length [m].
    """
    X = mesh.nodes
    return float(np.linalg.norm(X[mesh.node_sets[tip_set]].mean(axis=0) - X[mesh.node_sets[root_set]].mean(axis=0)))


def run_label(alpha, damping="global"):
    """How a run is named in its warnings: its damping.

    Parameters
    ----------
    alpha : float
        Mass-proportional damping [1/s].
    damping : str, optional
        "global" or "relative".

    Returns
    -------
    str
        ``"alpha = 180 1/s"`` (``"alpha = 180 1/s, relative damping"`` for relative).
    """
    return f"alpha = {alpha:g} 1/s" + ("" if damping == "global" else f", {damping} damping")


def issue(messages, label):
    """Issue each message once as a :class:`ccedi.errors.ValidityWarning`, prefixed by
    the run's label.

    Parameters
    ----------
    messages : list of str
        The warnings of one run (its summary's ``warnings``).
    label : str
        The run (:func:`run_label`).
    """
    for message in messages:
        warnings.warn(f"{label}: {message}", ValidityWarning, stacklevel=3)

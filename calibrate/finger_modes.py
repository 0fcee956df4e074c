"""The calibration's base model: the FE-derived modes of the declared finger, with a tip
mass and a compliant root added as Ritz terms.

The declared finger (length, elliptical section, nu, rho) is meshed as SM-A
(:func:`ccedi.fea.mesh.sm_a`), clamped at its root, and its lowest modes are solved once
at the declared E by the modal reductor's basis (:func:`ccedi.rom.modal.modal_basis`:
tangent stiffness at the reference, lumped mass M), the basis the impulse model's modal
ROM is made from. Of those, the modes that move the tip along the bending direction y
are kept (tip value above ``MIN_TIP_FRACTION`` of the largest), up to ``N_MAX_MODES``. Per kept mode i (mass-normalised phi_i):

    omega_i   angular frequency at the declared E [rad/s]; K is linear in E (neo-Hookean
              linearised at the reference: mu, lambda proportional to E), so at E x e the
              modes are the same and omega_i scales exactly as sqrt(e)
    b_i       tip value: the area-weighted mean y displacement of the tip face [1/sqrt(kg)]
    p_i       weight participation phi_i^T M e_y (a uniform transverse acceleration g gives
              the modal force p_i g) [sqrt(kg)]
    S_ki      the centre-line y displacement at Gauss points x_k along the finger (mass-
              weighted mean over each layer of nodes, interpolated) [1/sqrt(kg)]

Ritz additions (coordinates q_1..q_N and, for a compliant root, theta):

  tip mass m_t     M_r = I + m_t c c^T, c = (b, L): a point mass moving with the tip
  root compliance  the rigid rotation psi of the whole finger about the root's x axis
                   (u_y = z, u_z = -(y - y_root)), held by a rotational spring k_r:
                   M_r = [[I, Phi^T M psi], [psi^T M Phi, psi^T M psi]],
                   K_r = diag(e omega_i^2, k_r)   (a rigid rotation stores no strain energy)

The small eigenproblem K_r v = omega^2 M_r v gives the modes of the extended finger;
their tip values, weight participations and centre-line shapes are those of the Ritz
vectors combined by v. Building the FE modes costs seconds; they are cached per declared
finger (:func:`finger_basis`), and every fit evaluation solves only the small problem.
"""
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.linalg import eigh

from ccedi.errors import InputError
from ccedi.fea.material import NeoHookean
from ccedi.fea.mesh import sm_a
from ccedi.fea.model import cantilever_model, face_node_weights
from ccedi.rom.modal import modal_basis

N_SOLVED_MODES = 30
"""FE modes solved (every kind: both bending planes, torsion, axial); the y-bending ones are kept."""
N_MAX_MODES = 10
"""Most y-bending modes kept."""
MIN_TIP_FRACTION = 1e-3
"""A mode is kept when its |b_i| exceeds this fraction of the largest (the others bend in x,
twist or stretch and do not move the tip along y)."""
N_DRAG_POINTS = 8
"""Gauss-Legendre points along the finger at which distributed drag is evaluated."""


@dataclass(frozen=True)
class Modes:
    """Mass-normalised modes of the (extended) finger (module docstring).

    Parameters
    ----------
    omega_rad_s : numpy.ndarray
        Angular frequencies omega_i, ascending, (n,) [rad/s].
    tip : numpy.ndarray
        Tip values b_i (mean y displacement of the tip face), (n,) [1/sqrt(kg)], >= 0.
    weight : numpy.ndarray
        Weight participations p_i, (n,) [sqrt(kg)] (tip mass included).
    shapes : numpy.ndarray
        Centre-line y displacement at the drag points, (N_DRAG_POINTS, n) [1/sqrt(kg)].
    shape_weights : numpy.ndarray
        Gauss-Legendre weights of the drag points, (N_DRAG_POINTS,) [m].
    """

    omega_rad_s: np.ndarray
    tip: np.ndarray
    weight: np.ndarray
    shapes: np.ndarray
    shape_weights: np.ndarray

    @property
    def static_sag_per_g(self):
        """Static tip deflection per unit transverse acceleration [m / (m/s^2)]:
        sum b_i p_i / omega_i^2.
        """
        return float(np.sum(self.tip * self.weight / self.omega_rad_s**2))

    @property
    def static_flexibility_m_N(self):
        """Static tip deflection per unit tip force [m/N]: sum b_i^2 / omega_i^2."""
        return float(np.sum(self.tip**2 / self.omega_rad_s**2))


@dataclass(frozen=True)
class FingerBasis:
    """The FE modes of a declared finger at its declared E, with the root-rotation Ritz
    vector's couplings (module docstring). Build with :func:`finger_basis`.

    Parameters
    ----------
    length_m : float
        Finger length L [m] (root to tip face).
    mass_kg : float
        Finger mass, the sum of the lumped nodal masses [kg].
    omega_rad_s : numpy.ndarray
        Kept y-bending modes' angular frequencies at the declared E, (N,) [rad/s].
    tip : numpy.ndarray
        Their tip values b_i, (N,) [1/sqrt(kg)].
    weight : numpy.ndarray
        Their weight participations p_i, (N,) [sqrt(kg)].
    shapes : numpy.ndarray
        Their centre-line shapes at the drag points, (N_DRAG_POINTS, N) [1/sqrt(kg)].
    shape_weights : numpy.ndarray
        Gauss weights of the drag points (N_DRAG_POINTS,) [m].
    drag_points_m : numpy.ndarray
        Distances of the drag points from the root, (N_DRAG_POINTS,) [m].
    root_coupling : numpy.ndarray
        Phi^T M psi, (N,) [sqrt(kg) m/rad].
    root_inertia : float
        psi^T M psi, the finger's rotary inertia about the root axis [kg m^2].
    root_weight : float
        psi^T M e_y = sum m z, the weight participation of psi [kg m].
    """

    length_m: float
    mass_kg: float
    omega_rad_s: np.ndarray
    tip: np.ndarray
    weight: np.ndarray
    shapes: np.ndarray
    shape_weights: np.ndarray
    drag_points_m: np.ndarray
    root_coupling: np.ndarray
    root_inertia: float
    root_weight: float

    def modes(self, E_factor=1.0, *, tip_mass_kg=0.0, root_stiffness=None, n_modes=None):
        """Modes of the finger at E x ``E_factor`` with the Ritz additions (module docstring).

        Parameters
        ----------
        E_factor : float, optional
            Young's modulus over the declared one [-], > 0. Default 1.
        tip_mass_kg : float, optional
            Point mass at the tip [kg], >= 0. Default 0.
        root_stiffness : float or None, optional
            Rotational stiffness k_r of the clamp [N m/rad]; None for a rigid clamp.
        n_modes : int, optional
            Modes returned (the lowest); default all (N, or N + 1 with a compliant root).

        Returns
        -------
        Modes
            Frequencies, tip values, weight participations and drag-point shapes.

        Raises
        ------
        InputError
            ``E_factor`` not > 0, a negative tip mass or a root stiffness not > 0.
        """
        if not E_factor > 0.0 or not tip_mass_kg >= 0.0 or (root_stiffness is not None and not root_stiffness > 0.0):
            raise InputError(f"modes need E_factor > 0, tip_mass_kg >= 0 and root_stiffness > 0 (or None), got "
                             f"{E_factor!r}, {tip_mass_kg!r}, {root_stiffness!r}")
        n = len(self.omega_rad_s)
        w2 = E_factor * self.omega_rad_s**2
        if root_stiffness is None and tip_mass_kg == 0.0:
            m = Modes(np.sqrt(w2), self.tip.copy(), self.weight.copy(), self.shapes.copy(), self.shape_weights)
            return m if n_modes is None else _first(m, n_modes)
        c, p, S = self.tip, self.weight, self.shapes
        M = np.eye(n)
        K = np.diag(w2)
        if root_stiffness is not None:
            M = np.block([[M, self.root_coupling[:, None]], [self.root_coupling[None, :], np.full((1, 1), self.root_inertia)]])
            K = np.block([[K, np.zeros((n, 1))], [np.zeros((1, n)), np.full((1, 1), float(root_stiffness))]])
            c = np.append(c, self.length_m)
            p = np.append(p, self.root_weight)
            S = np.column_stack([S, self.drag_points_m])
        M = M + tip_mass_kg * np.outer(c, c)
        lam, vec = eigh(K, M)
        tip = c @ vec
        sign = np.where(tip < 0.0, -1.0, 1.0)
        vec = vec * sign
        m = Modes(omega_rad_s=np.sqrt(lam), tip=tip * sign, weight=p @ vec + tip_mass_kg * tip * sign,
                  shapes=S @ vec, shape_weights=self.shape_weights)
        return m if n_modes is None else _first(m, n_modes)


def _first(m, n):
    """The lowest ``n`` of the modes ``m``."""
    return Modes(m.omega_rad_s[:n], m.tip[:n], m.weight[:n], m.shapes[:, :n], m.shape_weights)


def centre_line(mesh, mass, phi_y, *, points_m):
    """Mass-weighted mean y displacement of each layer of nodes along z, at ``points_m``.

    Nodes are grouped by their distance z from the root (rounded to 1e-6 L; at most 400
    layers, else 100 equal bins), each group's mass-weighted mean is placed at its
    mass-weighted mean z, and the result is interpolated linearly at ``points_m``.

    Parameters
    ----------
    mesh : ccedi.fea.mesh.Mesh
        The finger (root at its smallest z).
    mass : numpy.ndarray
        Lumped nodal masses (n_nodes,) [kg].
    phi_y : numpy.ndarray
        y displacements of the nodes, (n_nodes, k) [any unit].
    points_m : numpy.ndarray
        Distances from the root at which to evaluate [m].

    Returns
    -------
    numpy.ndarray
        (len(points_m), k), in the unit of ``phi_y``.
    """
    z = mesh.nodes[:, 2] - mesh.nodes[:, 2].min()
    length = float(z.max())
    levels, group = np.unique(np.round(z / length, 6), return_inverse=True)
    if len(levels) > 400:
        group = np.minimum((z / length * 100).astype(int), 99)
    n_groups = int(group.max()) + 1
    mass_g = np.bincount(group, weights=mass, minlength=n_groups)
    ok = mass_g > 0
    z_g = np.bincount(group, weights=mass * z, minlength=n_groups)[ok] / mass_g[ok]
    out = np.empty((len(points_m), phi_y.shape[1]))
    for j in range(phi_y.shape[1]):
        mean = np.bincount(group, weights=mass * phi_y[:, j], minlength=n_groups)[ok] / mass_g[ok]
        out[:, j] = np.interp(points_m, z_g, mean)
    return out


@lru_cache(maxsize=8)
def finger_basis(length_m, semi_axes_m, *, nu, rho_kg_m3, E_Pa):
    """The FE basis of a declared finger, cached per finger (module docstring).

    Parameters
    ----------
    length_m : float
        Finger length [m].
    semi_axes_m : tuple of float
        Section semi-axes (a along x, b along y, the bending direction) [m].
    nu : float
        Poisson's ratio [-].
    rho_kg_m3 : float
        Density [kg/m^3].
    E_Pa : float
        The declared Young's modulus [Pa] (the modes' reference).

    Returns
    -------
    FingerBasis
        The kept y-bending modes and the root-rotation couplings.
    """
    mesh = sm_a(length_m=length_m, semi_axes_m=tuple(semi_axes_m))
    model = cantilever_model(mesh, NeoHookean(E=E_Pa, nu=nu, rho=rho_kg_m3))
    basis = modal_basis(model, N_SOLVED_MODES)
    omega, phi, mass = basis.omega_rad_s, basis.phi, basis.mass_kg
    tip_nodes = mesh.node_sets["tip"]
    tip = basis.weighted(tip_nodes, face_node_weights(mesh, tip_nodes), direction=1)
    keep = np.flatnonzero(np.abs(tip) > MIN_TIP_FRACTION * np.max(np.abs(tip)))[:N_MAX_MODES]
    sign = np.where(tip[keep] < 0.0, -1.0, 1.0)
    phi_k = phi[:, keep] * sign
    z0 = mesh.nodes[:, 2].min()
    root = mesh.node_sets["root"]
    y_root = float(np.mean(mesh.nodes[root, 1]))
    psi = np.zeros(3 * mesh.n_nodes)
    psi[1::3] = mesh.nodes[:, 2] - z0
    psi[2::3] = -(mesh.nodes[:, 1] - y_root)
    m3 = np.repeat(mass, 3)
    length = float(mesh.nodes[:, 2].max() - z0)
    xg, wg = np.polynomial.legendre.leggauss(N_DRAG_POINTS)
    points, weights = 0.5 * length * (xg + 1.0), 0.5 * length * wg
    return FingerBasis(length_m=length, mass_kg=float(mass.sum()), omega_rad_s=omega[keep], tip=tip[keep] * sign,
                       weight=mass @ phi_k[1::3], shapes=centre_line(mesh, mass, phi_k[1::3], points_m=points),
                       shape_weights=weights, drag_points_m=points, root_coupling=phi_k.T @ (m3 * psi),
                       root_inertia=float(psi @ (m3 * psi)), root_weight=float(mass @ psi[1::3]))

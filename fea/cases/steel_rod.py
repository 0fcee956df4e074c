"""The paper's section 2.2 example: a cantilevered steel rod with a tip mass.

Rod 0.4 m long, 0.6 mm in diameter, rho = 7957 kg/m^3, E = 209 GPa (0.90 g), with a
0.015 g point mass at its free end; 100 rod elements; an impulse of 0.003 N held for
0.2 s at the tip, perpendicular to the rod. Published (Ref. [13] of the paper): first
natural frequency 16.33 rad/s, damping ratio 0.0055; the paper's CCEDI search gives
alpha_cr = 30 1/s and alpha = zeta alpha_cr = 0.165 1/s. No gravity.

The rod lies along +z from the clamp at the origin and bends in y.
"""
import numpy as np

from ccedi.fea.cases.studies import FullImpulseModel
from ccedi.fea.elements.rod import RodSection, straight_rod
from ccedi.fea.mesh import Mesh
from ccedi.fea.model import ForcePulse, Model

STEEL_ROD = {"length_m": 0.4, "diameter_m": 0.6e-3, "rho_kg_per_m3": 7957.0, "E_Pa": 209e9,
             "tip_mass_kg": 0.015e-3, "n_elements": 100, "force_N": 0.003, "duration_s": 0.2}
"""Section 2.2 of the paper: geometry, material, tip mass, mesh and impulse."""

PAPER_ROD = {"omega1_rad_s": 16.33, "zeta": 0.0055, "alpha_cr_per_s": 30.0, "alpha_per_s": 0.165}
"""The paper's published values for the steel rod."""


def steel_rod_model(alpha=0.0, *, n_elements=STEEL_ROD["n_elements"], tip_mass_kg=STEEL_ROD["tip_mass_kg"],
                    force_N=STEEL_ROD["force_N"], duration_s=STEEL_ROD["duration_s"]):
    """Clamped steel rod with tip mass and tip impulse (force along +y), as a fea Model.

    Parameters
    ----------
    alpha : float, optional
        Mass-proportional damping coefficient [1/s].
    n_elements : int, optional
        Rod elements along the length.
    tip_mass_kg : float, optional
        Point mass at the free end [kg] (0: none).
    force_N : float, optional
        Tip force [N] along +y (0: no pulse).
    duration_s : float, optional
        How long the force is held [s].

    Returns
    -------
    ccedi.fea.model.Model
        Node sets: ``root`` (the two clamped nodes), ``tip`` (the free end, carrying the mass).
    """
    section = RodSection(E=STEEL_ROD["E_Pa"], rho=STEEL_ROD["rho_kg_per_m3"], diameter_m=STEEL_ROD["diameter_m"])
    nodes, rod, root, tip = straight_rod(STEEL_ROD["length_m"], n_elements, section)
    mesh = Mesh(nodes=nodes, hexes=np.zeros((0, 8), dtype=np.int64),
                node_sets={"root": np.asarray(root), "tip": np.array([tip])})
    pulses = ()
    if force_N:
        pulses = (ForcePulse(nodes=np.array([tip]), weights=np.ones(1), force_N=[0.0, force_N, 0.0],
                             t_start_s=0.0, t_end_s=duration_s),)
    point_masses = {tip: tip_mass_kg} if tip_mass_kg else {}
    return Model(mesh=mesh, material=None, alpha=alpha, fixed_nodes=np.asarray(root), pulses=pulses,
                 rods=(rod,), point_masses=point_masses)


def steel_rod_impulse_model(n_elements=STEEL_ROD["n_elements"], *, tip_mass_kg=STEEL_ROD["tip_mass_kg"],
                            force_N=STEEL_ROD["force_N"], duration_s=STEEL_ROD["duration_s"]):
    """The steel rod's impulse test as a :class:`ccedi.models.ImpulseModel`.

    Parameters
    ----------
    n_elements, tip_mass_kg, force_N, duration_s
        As :func:`steel_rod_model`.

    Returns
    -------
    ccedi.fea.cases.studies.FullImpulseModel
        ``run(alpha, t_end_s, n_outputs)`` integrates :func:`steel_rod_model` at ``alpha``;
        ``tip_uy_m`` is the free end's displacement along the load.
    """

    return FullImpulseModel(lambda alpha: steel_rod_model(alpha=alpha, n_elements=n_elements, tip_mass_kg=tip_mass_kg,
                                                          force_N=force_N, duration_s=duration_s),
                            force_N=force_N, duration_s=duration_s, name="fea-rod")

"""Impulse records with model-form error: the test set under ``data/measured_solid/``.

The bundled set (:mod:`ccedi.calibrate.synthetic`) is made from the same SM-A hexahedra and
matrices as the calibration's model, so it tests little model-form error. This set comes
from another discretisation of the declared 8-in finger, with the effects built into the
finite elements where they can be:

  mesh             SM-C (:func:`ccedi.fea.mesh.gmsh_fingers.sm_c`): Gmsh's unstructured
                   10-node tetrahedra at an average length of ``ELEMENT_SIZE_M``, curved
                   faces (the calibration uses SM-A's mapped hexahedra); at 4 mm 13428
                   nodes and 7893 elements, first frequency 4.502 Hz against SM-A's 4.496 Hz
  tip_mass         nodal masses on the tip face, by area (as the bundled set, on this mesh)
  root_compliance  a soft layer: the elements whose centroid lies within ``layer_depth_m``
                   of the clamp have E x ``layer_E_ratio`` (the calibration's model is a
                   rigid rotation of the whole finger on a rotational spring)
  viscoelastic     a one-term Prony series on the whole finger, or (``layer_depth_m``
                   given) on the root layer's elements only: a viscoelastic root, whose
                   relaxing stiffness is the layer's, phi^T K_layer phi in the modes
  the others       as :mod:`ccedi.calibrate.synthetic` (Rayleigh beta, nodal drag, tip
                   friction, sensor offset/drift and time delay), on this mesh

The solid is the linear FE solid (tangent stiffness at the reference, HRZ lumped mass),
reduced to its lowest ``N_GEN_MODES`` modes of every kind and integrated by Newmark with
the nonlinear forces on the nodes (:func:`ccedi.calibrate.synthetic.solid_response`). The
full explicit 3-D run is not used: on SM-C at 8 in the stable step is 1.88 us (manifest
``mesh.explicit_stable_step_s``), so a 2 s record takes a million steps of 13428 nodes:
the explicit run of :func:`ccedi.fea.cases.studies.finger_impulse_model` on this mesh took
61 s for 11 ms on the shared two cores (after compiling), about 3 hours per record.

Records are sampled at ``SAMPLE_RATE_HZ`` for 2 s, the displacement is written to
``DISPLACEMENT_RESOLUTION_M`` (far below the noise), and seeded white noise of 1 % of the
range is added. The set: each of 8 catalogued effects at two sizes, 4 clean controls (the
declared finger, one 5 % softer, one 6 % stiffer with more damping, and a 1 ms pulse) and
two declaration tests: the declared E 1.5 times the true one (the declaration must be
refused), and a correctly declared finger with a viscoelastic root (it must not be).

Regenerate: ``.venv/bin/python -m ccedi.calibrate.synthetic_solid [OUT_DIR [NAME ...]]``
(deterministic; 19 minutes for the whole set on two shared cores, the time is written to the
manifest; the records with quadratic damping take most, the drag being evaluated on every
node at every step).
"""
import json
import sys
import time
from functools import lru_cache
from pathlib import Path

import numpy as np

from ccedi.errors import InputError
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import Mesh
from ccedi.fea.mesh.gmsh_fingers import SM_C_ELEMENT_LENGTH, sm_c
from ccedi.fea.model import Model, cantilever_model
from ccedi.fea.solvers.explicit import critical_time_step
from ccedi.fea.solvers.static import tangent_stiffness
from ccedi.outputs import write_csv, write_json

from .synthetic import LENGTH_IN, N_GEN_MODES, NOISE_FRACTION, SHORT_PULSE, Truth, modal_system, record

ELEMENT_SIZE_M = SM_C_ELEMENT_LENGTH
"""Average element length of the SM-C mesh [m]."""
LAYER_DEPTH_M = 6e-3
"""Depth of the soft (or viscoelastic) root layer [m]."""
SAMPLE_RATE_HZ = 500.0
"""Sampling rate of the records [Hz]."""
DISPLACEMENT_RESOLUTION_M = 1e-8
"""The displacement is written rounded to this [m]."""
FORCE_N = 1.0
"""Tip pulse force of every record but the short-pulse control [N]."""
E_DECLARED_FACTOR = 1.5
"""Declared E over the true one in the wrong-declaration record [-]."""

INJECTED = {
    "stiffness_damping": ({"beta_s": 5e-4}, {"beta_s": 1.5e-3}),
    "viscoelastic": ({"prony_g": 0.1, "prony_tau_s": 0.05}, {"prony_g": 0.25, "prony_tau_s": 0.05}),
    "quadratic_damping": ({"drag_N_s2_m3": 3.0}, {"drag_N_s2_m3": 8.0}),
    "coulomb_friction": ({"friction_N": 0.003}, {"friction_N": 0.006}),
    "tip_mass": ({"tip_mass_kg": 0.004}, {"tip_mass_kg": 0.008}),
    "root_compliance": ({"layer_depth_m": LAYER_DEPTH_M, "layer_E_ratio": 0.3},
                        {"layer_depth_m": LAYER_DEPTH_M, "layer_E_ratio": 0.1}),
    "sensor_offset_drift": ({"offset_m": 2e-4, "drift_m_s": 4e-4}, {"offset_m": 4e-4, "drift_m_s": 8e-4}),
    "time_delay": ({"delay_s": 1e-3}, {"delay_s": 3e-3}),
}
"""Each effect's (low, high) size (generator parameters, SI units as named)."""
VISCOELASTIC_ROOT = {"prony_g": 0.9, "prony_tau_s": 0.03, "layer_depth_m": 0.02}
"""The viscoelastic root of the correctly declared finger: the first 20 mm relax to 10 % of
their stiffness with a 30 ms time constant (the baseline E then sits on its bound, 0.8,
while the record's first frequency is within E's reach)."""


@lru_cache(maxsize=4)
def finger_solid(element_size_m=ELEMENT_SIZE_M, layer_depth_m=LAYER_DEPTH_M):
    """The declared 8-in finger on SM-C, clamped, with the stiffness of its root layer.

    Parameters
    ----------
    element_size_m : float, optional
        Average element length [m]. Default ELEMENT_SIZE_M.
    layer_depth_m : float, optional
        The root layer: elements whose centroid lies within this distance of the clamp [m].
        Default LAYER_DEPTH_M.

    Returns
    -------
    model : ccedi.fea.model.Model
        The clamped finger at the declared E (RUBBER).
    stiffness : scipy.sparse.csr_matrix
        Its tangent stiffness at the reference, unconstrained [N/m].
    layer_stiffness : scipy.sparse.csr_matrix
        The part of it from the root layer's elements [N/m].
    """
    mesh = sm_c(LENGTH_IN, element_size_m=element_size_m)
    model = cantilever_model(mesh, RUBBER)
    centroid_z = mesh.nodes[mesh.tets10[:, :4], 2].mean(axis=1) - mesh.nodes[:, 2].min()
    layer = mesh.tets10[centroid_z < layer_depth_m]
    outside = np.setdiff1d(np.arange(mesh.n_nodes), layer)
    # the layer alone, every node outside it fixed (they have no mass in this model)
    layer_model = Model(mesh=Mesh(nodes=mesh.nodes, tets10=layer, node_sets=mesh.node_sets), material=RUBBER,
                        fixed_nodes=outside)
    return model, tangent_stiffness(model).tocsr(), tangent_stiffness(layer_model).tocsr()


def system_of(truth: Truth, element_size_m=ELEMENT_SIZE_M):
    """The modes of the SM-C solid with the truth's tip mass, soft root layer and
    viscoelastic part built in (module docstring).

    Parameters
    ----------
    truth : Truth
        E factor and effects.
    element_size_m : float, optional
        Average element length [m]. Default ELEMENT_SIZE_M.

    Returns
    -------
    ccedi.calibrate.synthetic.SolidSystem
        The lowest N_GEN_MODES modes.
    """
    fx = truth.effects
    root = fx.get("root_compliance", {})
    ve = fx.get("viscoelastic", {})
    depth = root.get("layer_depth_m", ve.get("layer_depth_m", LAYER_DEPTH_M))
    model, K, K_layer = finger_solid(element_size_m, depth)
    soft = root.get("layer_E_ratio", 1.0)
    stiffness = truth.E_factor * (K + (soft - 1.0) * K_layer)
    relaxing = truth.E_factor * soft * K_layer if "layer_depth_m" in ve else None
    return modal_system(model, stiffness, tip_mass_kg=fx.get("tip_mass", {}).get("tip_mass_kg", 0.0),
                        relaxing=relaxing)


def solid_set():
    """The truths of the set (module docstring), with their role.

    Returns
    -------
    dict
        {record name: (Truth, role, declared E over the true one [-])}; role ``effect``,
        ``control`` or ``declaration``.
    """
    rng = np.random.default_rng(2026)

    def truth(effects=None, E=None, alpha=None, **kw):
        return Truth(E_factor=float(rng.uniform(0.92, 1.08)) if E is None else E,
                     alpha_per_s=float(rng.uniform(3.0, 5.0)) if alpha is None else alpha,
                     force_N=kw.pop("force_N", FORCE_N), effects=effects or {}, **kw)

    out = {}
    for name, sizes in INJECTED.items():
        for size, params in zip(("low", "high"), sizes):
            out[f"{name}_{size}"] = (truth({name: params}), "effect", 1.0)
    out["control_declared"] = (truth(E=1.0, alpha=4.0), "control", 1.0)
    out["control_soft_5pct"] = (truth(E=0.95, alpha=3.5), "control", 1.0)
    out["control_stiff_6pct"] = (truth(E=1.06, alpha=8.0), "control", 1.0)
    out["control_short_pulse"] = (truth(force_N=SHORT_PULSE["force_N"], duration_s=SHORT_PULSE["duration_s"]),
                                  "control", 1.0)
    out["declared_E_x1.5"] = (truth(E=1.0, alpha=4.0), "declaration", E_DECLARED_FACTOR)
    out["viscoelastic_root_declared"] = (truth({"viscoelastic": VISCOELASTIC_ROOT}, E=1.0, alpha=4.0), "declaration",
                                         1.0)
    return out


def solid_record(truth: Truth, seed, *, declared_E_factor=1.0, element_size_m=ELEMENT_SIZE_M):
    """One record of the set: SM-C solid, sensor, sampling at SAMPLE_RATE_HZ, noise.

    Parameters
    ----------
    truth : Truth
        What the record contains (E factor over the finger's true RUBBER.E).
    seed : int
        Seed of the white measurement noise.
    declared_E_factor : float, optional
        The E the sidecar declares, over RUBBER.E [-]. Default 1.
    element_size_m : float, optional
        Average element length of SM-C [m]. Default ELEMENT_SIZE_M.

    Returns
    -------
    frame : pandas.DataFrame
        Columns ``time_s`` [s], ``tip_displacement_m`` [m], ``force_N`` [N].
    meta : dict
        The JSON sidecar.
    """
    frame, meta = record(truth, seed, system=system_of(truth, element_size_m), sample_rate_hz=SAMPLE_RATE_HZ)
    frame["tip_displacement_m"] = np.round(frame["tip_displacement_m"] / DISPLACEMENT_RESOLUTION_M) \
        * DISPLACEMENT_RESOLUTION_M
    meta["finger"]["E_Pa"] = declared_E_factor * RUBBER.E
    return frame, meta


def write_solid_set(out_dir, names=None):
    """Write every record (or those named) as NAME.csv + NAME.json and the truths as
    manifest.json.

    Deterministic; prints one line per record. The manifest keeps the time of the last
    full run (``generation_time_s``) when only some records are written into a folder
    that has one.

    Parameters
    ----------
    out_dir : str or pathlib.Path
        Output directory (created if missing).
    names : iterable of str or None, optional
        The records to write; None: all. Default None.

    Raises
    ------
    InputError
        A name that is not a record of the set.
    """
    out_dir = Path(out_dir)
    start = time.perf_counter()
    model = finger_solid()[0]
    cases = solid_set()
    unknown = sorted(set(names or ()) - set(cases))
    if unknown:
        raise InputError(f"{', '.join(unknown)}: not records of the set ({', '.join(cases)})")
    manifest = {}
    for i, (name, (truth, role, declared)) in enumerate(cases.items()):
        manifest[name] = {"role": role, "E_factor": truth.E_factor / declared, "true_E_factor": truth.E_factor,
                          "declared_E_factor": declared, "alpha_per_s": truth.alpha_per_s, "force_N": truth.force_N,
                          "duration_s": truth.duration_s, "effects": truth.effects,
                          "declaration_right": declared == 1.0}
        if names is not None and name not in names:
            continue
        frame, meta = solid_record(truth, seed=3000 + i, declared_E_factor=declared)
        write_csv(out_dir / f"{name}.csv", frame)
        write_json(out_dir / f"{name}.json", meta)
        print(f"{name}: E x {truth.E_factor:.3f} (declared x {declared:g}), alpha {truth.alpha_per_s:.2f} 1/s, "
              f"{truth.effects}", flush=True)
    elapsed = time.perf_counter() - start
    if names is not None and (out_dir / "manifest.json").is_file():
        elapsed = json.loads((out_dir / "manifest.json").read_text())["generation_time_s"]
    write_json(out_dir / "manifest.json", {
        "generator": f"ccedi.calibrate.synthetic_solid (linear FE solid, SM-C tet10 {1e3 * ELEMENT_SIZE_M:g} mm, "
                     f"{N_GEN_MODES} modes, Newmark)",
        "mesh": {"element_type": model.mesh.element_type, "nodes": model.mesh.n_nodes,
                 "elements": model.mesh.n_elements, "explicit_stable_step_s": critical_time_step(model)},
        "E_factor_is": "true E over the declared E", "sample_rate_hz": SAMPLE_RATE_HZ,
        "noise_fraction": NOISE_FRACTION, "generation_time_s": elapsed, "records": manifest})


if __name__ == "__main__":
    write_solid_set(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).parents[1] / "data" / "measured_solid",
                    names=sys.argv[2:] or None)

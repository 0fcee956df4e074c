"""Speed of the static and eigen solves: Table 1's tip stiffness and first frequency.

For SM-A, SM-B and SM-C (4.5 in; ``--detailed`` adds the detailed model DM, whose
nonlinear solves take many minutes), each in a process of its own per variant: the tip
stiffness (two nonlinear static solves, 1 N and 2 N, :func:`ccedi.fea.solvers.static.tip_stiffness`)
and the first natural frequency (:func:`ccedi.fea.solvers.modal.natural_frequencies`),
timed, with the number of factorisations of the tangent. Variants:

* ``reuse``: each Newton correction by conjugate gradients preconditioned with an earlier
  tangent's factors, new factors when 12 iterations do not converge (the code's choice
  with SuperLU);
* ``full``: a factorisation every Newton iteration (``PRECONDITIONED_ITERATIONS`` 0,
  direct full Newton);

each with the process's sparse solver (:data:`ccedi.fea.solvers.linear.SOLVER`: PARDISO
when pypardiso is installed, else SuperLU) and, when PARDISO is there, with SuperLU forced
too. Prints and writes benchmarks/static_speed.json: the times, the speed-up of each
variant over ``full`` with SuperLU, and the largest relative difference of the figures
between variants (Table 1's figures must agree within 1e-6).

Run: ``.venv/bin/python benchmarks/static_speed.py [--detailed]``.
"""
import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import sm_a, sm_b
from ccedi.fea.mesh.gmsh_fingers import detailed_model, sm_c
from ccedi.fea.model import cantilever_model
from ccedi.fea.solvers import linear, modal, static
from ccedi.outputs import report_figures

OUT = Path(__file__).with_suffix(".json")
MESHES = ("SM-A", "SM-B", "SM-C")


def measure(mesh_name, variant):
    """One process's figures: stiffness [N/m], omega_1 [rad/s], their times [s] and the
    factorisations, for ``mesh_name`` with ``variant`` ("reuse" or "full")."""
    meshes = {"SM-A": lambda: sm_a(length_in=4.5), "SM-B": lambda: sm_b(length_in=4.5),
              "SM-C": lambda: sm_c(length_in=4.5), "DM": detailed_model}
    model = cantilever_model(meshes[mesh_name](), RUBBER)
    static.PRECONDITIONED_ITERATIONS = {solver: 0 if variant == "full" else 12 for solver in linear.SOLVERS}
    made = []
    original = linear.Factorization

    class Counted(original):
        def __init__(self, K, solver=None):
            made.append(K.shape[0])
            super().__init__(K, solver)

    def refactorized(self, K):
        before = len(made)
        new = original.refactorized(self, K)
        if len(made) == before:                      # numerical refactorisation (a new one is counted above)
            made.append(K.shape[0])
        return new

    Counted.refactorized = refactorized
    static.Factorization = modal.Factorization = Counted
    t0 = time.perf_counter()
    k = static.tip_stiffness(model, (1.0, 2.0))
    t1 = time.perf_counter()
    factorisations = len(made)
    omega = float(modal.natural_frequencies(model, n_modes=1)[0])
    t2 = time.perf_counter()
    return {"dofs": 3 * model.mesh.n_nodes, "solver": linear.SOLVER, "stiffness_N_per_m": k,
            "stiffness_s": t1 - t0, "factorisations": factorisations, "omega1_rad_s": omega, "omega1_s": t2 - t1}


def child(mesh_name, variant, solver=None):
    env = dict(os.environ)
    if solver is not None:
        env["CCEDI_SPARSE_SOLVER"] = solver
    done = subprocess.run([sys.executable, __file__, "--child", mesh_name, variant], capture_output=True, text=True,
                          env=env, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--detailed", action="store_true", help="add the detailed model DM (many minutes)")
    parser.add_argument("--child", nargs=2, metavar=("MESH", "VARIANT"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(measure(*args.child)))
        return
    variants = [("full", "superlu"), ("reuse", "superlu")]
    if linear.pypardiso is not None:
        variants += [("full", "pardiso"), ("reuse", "pardiso")]
    figures = {"solvers_available": ["superlu"] + (["pardiso"] if linear.pypardiso is not None else [])}
    for name in MESHES + (("DM",) if args.detailed else ()):
        rows = {f"{v}_{s}": child(name, v, s) for v, s in variants}
        base = rows["full_superlu"]
        for label, row in rows.items():
            print(f"{name} {label}: stiffness {row['stiffness_N_per_m']:.6g} N/m in {row['stiffness_s']:.2f} s "
                  f"({row['factorisations']} factorisations), omega1 {row['omega1_rad_s']:.6g} rad/s in "
                  f"{row['omega1_s']:.2f} s", flush=True)
        figures[name] = {
            "dofs": base["dofs"], **rows,
            "speedup_over_full_superlu": {label: round((base["stiffness_s"] + base["omega1_s"])
                                                       / (row["stiffness_s"] + row["omega1_s"]), 2)
                                          for label, row in rows.items()},
            "largest_relative_difference": max(max(abs(row[k] / base[k] - 1.0) for k in ("stiffness_N_per_m",
                                                                                           "omega1_rad_s"))
                                               for row in rows.values()),
        }
    figures["load_average_after"] = round(os.getloadavg()[0], 2)
    figures["cores"] = os.cpu_count()
    report_figures(figures, OUT)


if __name__ == "__main__":
    main()

"""The hexahedron's internal forces on a CUDA GPU, many runs of SM-A at once, against the
CPU kernels (optional: needs numba-cuda and a GPU; says so and writes that where none is).

``--prepare`` (where ccedi is installed) writes benchmarks/gpu_speed_case.npz: SM-A 4.5 in
(725 hexahedra) and its element arrays, and for four perturbed states (positions
X + 50 um noise, velocities 0.1 m/s noise, numpy's generator seeded 0..3) the forces,
critical step and energies of the CPU kernel
(:func:`ccedi.fea.elements.hex8_kernels.internal_forces_numba`). Without ``--prepare`` the
script needs only numpy and numba-cuda (it loads ``fea/elements/hex8_cuda.py`` by path), so
that it runs on a GPU machine where ccedi's other dependencies are not installed: for
1, 32, 1000 and 10 000 runs (runs innermost; run k's state from the generator seeded k) it
times :func:`internal_forces` (element forces and the ordered node sums; best of 10 after a
warm-up launch, synchronised) in ns per element and run, and checks runs 0-3 against the
CPU kernel's forces (largest difference over the largest force) and critical step.

Writes benchmarks/gpu_speed.json. Run: ``.venv/bin/python benchmarks/gpu_speed.py --prepare``
here, then ``python3 benchmarks/gpu_speed.py`` on the GPU machine.
"""
import argparse
import importlib.util
import json
import os
import platform
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
CASE = HERE / "gpu_speed_case.npz"
OUT = HERE / "gpu_speed.json"
RUNS = (1, 32, 1000, 10000)
CHECKED = 4


def state(X, seed):
    """Run ``seed``'s positions and velocities: small noise around the reference."""
    rng = np.random.default_rng(seed)
    return X + 5e-5 * rng.standard_normal(X.shape), 0.1 * rng.standard_normal(X.shape)


def prepare():
    """Write the case file with the CPU kernel's reference results (needs ccedi)."""
    from ccedi.fea.elements.hex8 import BULK_VISCOSITY_C0, BULK_VISCOSITY_C1
    from ccedi.fea.elements.hex8_kernels import FACES, HOURGLASS_BASE, internal_forces_numba
    from ccedi.fea.material import RUBBER
    from ccedi.fea.mesh import sm_a
    from ccedi.fea.model import cantilever_model

    model = cantilever_model(sm_a(length_in=4.5), RUBBER)
    X, hexes, g = model.mesh.nodes, model.mesh.hexes, model.geometry
    mu, lam, rho, c = model.solid_constants
    forces, dts, energies = [], [], []
    for seed in range(CHECKED):
        x, v = state(X, seed)
        f = np.zeros_like(X)
        dt, ws, whg, pb, status = internal_forces_numba(x, v, model.hexahedra, model.solid_constants, f)
        forces.append(f)
        dts.append(dt)
        energies.append((ws, whg, pb))
    np.savez(CASE, X=X, hexes=hexes.astype(np.int64), b=g.b, vol=g.volume,
             centre=np.einsum("ak,eki->eai", HOURGLASS_BASE, X[hexes]).reshape(len(hexes), 12), kappa=model.kappa,
             H=HOURGLASS_BASE, faces=np.asarray(FACES, dtype=np.int64),
             params=np.array([mu, lam, rho, c, model.hex_length_factor, BULK_VISCOSITY_C0, BULK_VISCOSITY_C1]),
             ref_forces=np.array(forces), ref_dt=np.array(dts), ref_energies=np.array(energies))
    print(f"wrote {CASE}")


def measure():
    """Time the GPU kernels and check them against the CPU kernel (module docstring)."""
    if not hasattr(np, "row_stack"):          # numba-cuda 0.2x registers np.row_stack, gone in numpy 2.4
        np.row_stack = np.vstack
    from numba import cuda

    figures = {"machine": platform.node(), "python": platform.python_version()}
    if not cuda.is_available():
        figures["gpu"] = None
        figures["note"] = "no CUDA GPU here: nothing measured"
        print(figures["note"])
        OUT.write_text(json.dumps(figures, indent=1))
        return
    spec = importlib.util.spec_from_file_location("hex8_cuda", HERE.parent / "fea" / "elements" / "hex8_cuda.py")
    hc = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hc)
    case = np.load(CASE)
    X, hexes = case["X"], case["hexes"]
    start, element, corner = hc.node_slots(hexes, len(X))
    mesh = {k: cuda.to_device(np.ascontiguousarray(case[k])) for k in ("hexes", "b", "vol", "centre", "kappa", "H",
                                                                    "faces")}
    mesh |= {"node_start": cuda.to_device(start), "node_element": cuda.to_device(element),
             "node_corner": cuda.to_device(corner)}
    params = cuda.to_device(case["params"])
    figures["gpu"] = cuda.get_current_device().name.decode() if isinstance(cuda.get_current_device().name, bytes) \
        else str(cuda.get_current_device().name)
    figures["elements"] = int(len(hexes))
    for runs in RUNS:
        states = [state(X, k) for k in range(runs)]
        x = cuda.to_device(np.ascontiguousarray(np.stack([s[0] for s in states], axis=-1)))
        v = cuda.to_device(np.ascontiguousarray(np.stack([s[1] for s in states], axis=-1)))
        f, values = hc.internal_forces(x, v, mesh_arrays=mesh, params=params)                    # warm-up (compiles)
        cuda.synchronize()
        best = np.inf
        for _ in range(10):
            t0 = time.perf_counter()
            f, values = hc.internal_forces(x, v, mesh_arrays=mesh, params=params)
            cuda.synchronize()
            best = min(best, time.perf_counter() - t0)
        figures[f"runs_{runs}_best_s"] = best
        figures[f"runs_{runs}_ns_per_element_and_run"] = 1e9 * best / (len(hexes) * runs)
        if runs >= CHECKED:
            f_host, values_host = f.copy_to_host(), values.copy_to_host()
            ref = case["ref_forces"]
            figures["largest_force_difference_over_largest_force"] = float(max(
                np.abs(f_host[:, :, k] - ref[k]).max() / np.abs(ref[k]).max() for k in range(CHECKED)))
            figures["critical_step_relative_difference"] = float(max(
                abs(values_host[:, 1, k].min() / case["ref_dt"][k] - 1.0) for k in range(CHECKED)))
            figures["strain_energy_relative_difference"] = float(max(
                abs(values_host[:, 2, k].sum() / case["ref_energies"][k][0] - 1.0) for k in range(CHECKED)))
        print(f"{runs} runs: {figures[f'runs_{runs}_ns_per_element_and_run']:.3f} ns per element and run", flush=True)
    for key, value in figures.items():
        print(key, value)
    OUT.write_text(json.dumps(figures, indent=1))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--prepare", action="store_true", help="write the case file (needs ccedi)")
    if parser.parse_args().prepare:
        prepare()
    else:
        measure()


if __name__ == "__main__":
    os.environ.setdefault("NUMBA_CUDA_LOW_OCCUPANCY_WARNINGS", "0")
    main()

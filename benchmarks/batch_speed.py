"""Speed of batched runs (lanes across runs) against single runs, and of the CCEDI search.

SM-A 4.5-in finger, 1 N tip impulse for 10 ms, 8 alphas from 120 to 260 1/s, 0.2 s each.
Each variant runs in a process of its own (a variant compiled later in a process runs
slower than the same code compiled first, so in-process comparisons are biased), one
after the other, with the load average recorded before and after:

* ``kernel``: the internal-force kernel alone at a perturbed state, best of many short
  batches [ns per element and run]: the single-run kernel (lanes across elements) and the
  lanes kernel at 4 and 8 runs per call (lanes across runs);
* ``sweep``: the 8 runs as single runs one after the other (``run``, 2 threads each), and
  batched (``run_batch``) on 1 thread (one group of 8 lanes) and on 2 (two groups of 4):
  wall time [s] and ns per element-cycle per run (wall x threads / (steps x elements));
  every batched run's history and final state compared, bit for bit, with its single run;
* ``search``: the alpha_cr search of the finger (rtol 1 %) by bisection on the full model
  (:func:`ccedi.rom.ccedi.critical_alpha`) and narrowed by the modal ROM
  (:func:`ccedi.rom.finger_identification.finger_alpha_cr` as it is called by default:
  two full runs 0.95 rtol apart around the ROM's alpha_cr): wall time, runs, alpha_cr and
  bracket.

Prints and writes benchmarks/batch_speed.json. Run: ``.venv/bin/python benchmarks/batch_speed.py``.
"""
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numba as nb
import numpy as np

from ccedi.fea.cases.studies import finger_impulse_model
from ccedi.fea.elements.hex8_kernels import internal_forces_numba
from ccedi.fea.elements.hex8_lanes import full_stiffness, lanes_kernel
from ccedi.fea.material import RUBBER
from ccedi.fea.mesh import sm_a
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.fea.solvers.batch import run_batch
from ccedi.fea.solvers.explicit import SolidMaterial, run
from ccedi.outputs import report_figures
from ccedi.rom.finger_identification import finger_alpha_cr

OUT = Path(__file__).with_suffix(".json")
ALPHAS = np.linspace(120.0, 260.0, 8)
T_END_S = 0.2
TARGET_NS = 70.0
TARGET_SWEEP_S = 12.0


def _models():
    mesh = sm_a(length_in=4.5)
    return [cantilever_model(mesh, RUBBER, alpha=a, pulses=[tip_pulse(mesh, [0.0, 1.0, 0.0], 0.01)]) for a in ALPHAS]


def _best_ns(call, n_elem, runs, batches=200, calls=5):
    call()
    best = np.inf
    for _ in range(batches):
        t0 = time.perf_counter()
        for _ in range(calls):
            call()
        best = min(best, (time.perf_counter() - t0) / calls)
    return 1e9 * best / (n_elem * runs)


def part_kernel(lanes):
    """Kernel alone [ns per element and run]; lanes 1: the single-run kernel."""
    model = _models()[0]
    mesh, group, material = model.mesh, model.hexahedra, SolidMaterial(*model.solid_constants)
    nb.set_num_threads(1)
    rng = np.random.default_rng(0)
    n = max(lanes, 1)
    x = mesh.nodes[:, :, None] + 1e-4 * rng.standard_normal(mesh.nodes.shape + (n,))
    v = 0.1 * rng.standard_normal(x.shape)
    f = np.zeros_like(x)
    if lanes == 1:
        x1, v1, f1 = (np.ascontiguousarray(a[:, :, 0]) for a in (x, v, f))
        return _best_ns(lambda: internal_forces_numba(x1, v1, group, material, f1), mesh.n_elements, 1)
    kernel, stiffness, result = lanes_kernel(lanes), full_stiffness(group), np.zeros((5, lanes))
    return _best_ns(lambda: kernel(x, v, group, stiffness, material, 0, f, result), mesh.n_elements, lanes)


def part_sweep(mode):
    """The 8-run sweep: ``single`` or ``batch1`` / ``batch2`` (threads)."""
    models = _models()
    n_elem = models[0].mesh.n_elements
    if mode == "single":
        run(models[0], 1e-3, n_outputs=1, threads=2)
        t0 = time.perf_counter()
        results = [run(m, T_END_S, threads=2) for m in models]
        threads = 2
    else:
        threads = int(mode[-1])
        run_batch(models, 1e-3, n_outputs=1, threads=threads)
        t0 = time.perf_counter()
        results = run_batch(models, T_END_S, threads=threads)
    wall = time.perf_counter() - t0
    steps = sum(r.summary["steps"] for r in results)
    np.savez(f"/tmp/ccedi_batch_speed_{mode}.npz", *[r.history.to_numpy() for r in results],
             *[r.x for r in results])
    return {"wall_s": wall, "steps": steps, "threads": threads,
            "ns_per_element_cycle_per_run": 1e9 * wall * threads / (steps * n_elem)}


def part_search(mode):
    """alpha_cr of the 4.5-in finger: ``bisection`` or ``rom_narrowed`` (finger_alpha_cr's default)."""
    model = finger_impulse_model(4.5)                      # compile outside the timing
    model.run(100.0, 1e-3, 1)
    model.run_many([100.0, 120.0], 1e-3, 1)
    t0 = time.perf_counter()
    crit, _ = finger_alpha_cr(4.5, rtol=0.01, **({"runs_per_round": 1} if mode == "bisection" else {}))
    return {"wall_s": time.perf_counter() - t0, "runs": crit.n_runs, "alpha_cr_per_s": crit.alpha_cr_per_s,
            "bracket_per_s": list(crit.bracket_per_s), "reduced_alpha_cr_per_s": crit.reduced_alpha_cr_per_s}


def _in_process(part, arg):
    out = subprocess.run([sys.executable, __file__, part, str(arg)], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _same_bits(a, b):
    first, second = np.load(f"/tmp/ccedi_batch_speed_{a}.npz"), np.load(f"/tmp/ccedi_batch_speed_{b}.npz")
    return all(np.array_equal(first[k], second[k]) for k in first.files)


def main():
    load_before = os.getloadavg()[0]
    kernel = {f"lanes_{k}": _in_process("kernel", k) for k in (1, 4, 8)}
    sweep = {mode: _in_process("sweep", mode) for mode in ("single", "batch1", "batch2")}
    search = {mode: _in_process("search", mode) for mode in ("bisection", "rom_narrowed")}
    figures = {
        "model": f"SM-A 4.5 in, 725 hex8, 1 N for 10 ms, {len(ALPHAS)} alphas {ALPHAS[0]:g}-{ALPHAS[-1]:g} 1/s, "
                 f"{T_END_S} s",
        "kernel_ns_per_element_and_run_single_run_kernel": round(kernel["lanes_1"], 1),
        "kernel_ns_per_element_and_run_4_lanes": round(kernel["lanes_4"], 1),
        "kernel_ns_per_element_and_run_8_lanes": round(kernel["lanes_8"], 1),
        "sweep_wall_s_single_runs_2_threads": round(sweep["single"]["wall_s"], 2),
        "sweep_wall_s_batched_1_thread": round(sweep["batch1"]["wall_s"], 2),
        "sweep_wall_s_batched_2_threads": round(sweep["batch2"]["wall_s"], 2),
        "ns_per_element_cycle_per_run_single_runs_2_threads": round(sweep["single"]["ns_per_element_cycle_per_run"], 1),
        "ns_per_element_cycle_per_run_batched_1_thread": round(sweep["batch1"]["ns_per_element_cycle_per_run"], 1),
        "ns_per_element_cycle_per_run_batched_2_threads": round(sweep["batch2"]["ns_per_element_cycle_per_run"], 1),
        "target_ns_per_element_cycle_per_run_one_core": TARGET_NS,
        "target_sweep_wall_s_two_cores": TARGET_SWEEP_S,
        "batched_runs_bit_identical_to_single_runs": _same_bits("single", "batch1") and _same_bits("single", "batch2"),
        "search_bisection": search["bisection"],
        "search_rom_narrowed": search["rom_narrowed"],
        "search_speedup": round(search["bisection"]["wall_s"] / search["rom_narrowed"]["wall_s"], 2),
        "load_average_before": round(load_before, 2),
        "load_average_after": round(os.getloadavg()[0], 2),
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "machine": platform.machine(),
    }
    report_figures(figures, OUT)


if __name__ == "__main__":
    if len(sys.argv) == 3:
        part = {"kernel": lambda a: part_kernel(int(a)), "sweep": part_sweep, "search": part_search}[sys.argv[1]]
        print(json.dumps(part(sys.argv[2])))
    else:
        main()

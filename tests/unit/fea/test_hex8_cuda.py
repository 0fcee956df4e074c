"""The GPU hexahedron kernels (optional path) against the CPU kernel, in numba's CUDA
simulator: the same arithmetic, so the same forces, step and energies, on any machine."""
import json
import os
import subprocess
import sys
import textwrap

SCRIPT = textwrap.dedent("""
    import json
    import numpy as np
    from ccedi.fea.elements import hex8_cuda as hc
    from ccedi.fea.elements.hex8 import BULK_VISCOSITY_C0, BULK_VISCOSITY_C1
    from ccedi.fea.elements.hex8_kernels import FACES, HOURGLASS_BASE, internal_forces_numba
    from ccedi.fea.material import RUBBER
    from ccedi.fea.mesh import elliptical_cantilever
    from ccedi.fea.model import cantilever_model

    model = cantilever_model(elliptical_cantilever(0.05, 2, 4), RUBBER)
    X, hexes, g = model.mesh.nodes, model.mesh.hexes, model.geometry
    start, element, corner = hc.node_slots(hexes, len(X))
    mesh = {"hexes": hexes.astype(np.int64), "b": g.b, "vol": g.volume,
            "centre": np.einsum("ak,eki->eai", HOURGLASS_BASE, X[hexes]).reshape(len(hexes), 12),
            "kappa": model.kappa, "H": HOURGLASS_BASE, "faces": np.asarray(FACES, dtype=np.int64),
            "node_start": start, "node_element": element, "node_corner": corner}
    params = np.array([*model.solid_constants, model.hex_length_factor, BULK_VISCOSITY_C0, BULK_VISCOSITY_C1])
    rngs = [np.random.default_rng(k) for k in range(3)]
    states = [(X + 2e-4 * r.standard_normal(X.shape), 0.5 * r.standard_normal(X.shape)) for r in rngs]
    x = np.ascontiguousarray(np.stack([s[0] for s in states], axis=-1))
    v = np.ascontiguousarray(np.stack([s[1] for s in states], axis=-1))
    f, values = hc.internal_forces(x, v, mesh_arrays=mesh, params=params, threads_per_block=32)
    f = np.asarray(f.copy_to_host() if hasattr(f, "copy_to_host") else f)
    values = np.asarray(values.copy_to_host() if hasattr(values, "copy_to_host") else values)
    out = []
    for k, (xk, vk) in enumerate(states):
        ref = np.zeros_like(X)
        dt, ws, whg, pb, status = internal_forces_numba(xk, vk, model.hexahedra, model.solid_constants, ref)
        out.append([float(np.abs(f[:, :, k] - ref).max() / np.abs(ref).max()),
                    float(values[:, 1, k].min() / dt - 1.0), float(values[:, 2, k].sum() / ws - 1.0),
                    float(values[:, 3, k].sum() / whg - 1.0), float(values[:, 4, k].sum() / pb - 1.0),
                    bool((values[:, 0, k] > 0).all())])
    print(json.dumps(out))
""")


def test_the_gpu_kernels_give_the_cpu_kernels_forces_in_the_simulator():
    """Three runs of a small finger with perturbed positions and velocities (the bulk
    viscosity acting in the compressed elements): forces, smallest critical step and the
    three energies of every run within 1e-12 of the CPU kernel's."""
    env = dict(os.environ, NUMBA_ENABLE_CUDASIM="1")
    done = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    for force, dt, strain, hourglass, bulk, positive in json.loads(done.stdout.strip().splitlines()[-1]):
        assert positive
        assert force <= 1e-12 and abs(dt) <= 1e-12 and abs(strain) <= 1e-12
        assert abs(hourglass) <= 1e-12 and abs(bulk) <= 1e-12

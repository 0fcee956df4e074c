import sys, time
import numpy as np, numba as nb
from ccedi.fea.elements.hex8_kernels import internal_forces_numba
import sys
from ccedi.fea.elements.hex8_lanes import lanes_kernel, full_stiffness
LANES = int(sys.argv[1]) if len(sys.argv) > 1 else 8
internal_forces_lanes = lanes_kernel(LANES)
from ccedi.fea.mesh import sm_a
from ccedi.fea.model import cantilever_model, tip_pulse
from ccedi.fea.solvers.explicit import SolidMaterial
from ccedi.fea.material import RUBBER
mesh = sm_a(length_in=4.5)
model = cantilever_model(mesh, RUBBER, alpha=180.0, pulses=[tip_pulse(mesh, [0.0, 1.0, 0.0], 0.01)])
B = LANES
rng = np.random.default_rng(0)
x = model.mesh.nodes[:, :, None] + 1e-4 * rng.standard_normal(model.mesh.nodes.shape + (B,))
v = 0.1 * rng.standard_normal(x.shape)
f = np.zeros_like(x)
material = SolidMaterial(*model.solid_constants)
g = model.hexahedra; K = full_stiffness(g)
nb.set_num_threads(1)
res = np.zeros((5, B))
internal_forces_lanes(x, v, g, K, material, 0, f, res)
ok = True
for b in range(B):
    fs = np.zeros(mesh.nodes.shape)
    r = internal_forces_numba(np.ascontiguousarray(x[:, :, b]), np.ascontiguousarray(v[:, :, b]), g, material, fs)
    same = np.array_equal(fs, f[:, :, b]) and all(r[i] == res[i, b] for i in range(4)) and r[4] == res[4, b]
    ok &= same
    if not same: print(b, np.abs(fs - f[:, :, b]).max(), r, res[:, b])
print("bit-identical", ok)
best = np.inf
for _ in range(100):
    t0 = time.perf_counter()
    for _ in range(5):
        internal_forces_lanes(x, v, g, K, material, 0, f, res)
    best = min(best, (time.perf_counter() - t0) / 5)
print("lanes", B, "kernel", round(1e9 * best / mesh.n_elements / B, 1), "ns/elem-run")

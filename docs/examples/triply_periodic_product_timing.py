"""Time the fast triply periodic product (docs/periodic.md): N unit spheres on a jittered
cubic lattice at volume fraction 0.2, tolerance 1e-6, F and FTS by default (or the
moments given after N); best of two products after a warm-up.

    target/python-venv/bin/python docs/examples/triply_periodic_product_timing.py 10000 F FT FTS
"""
import time, numpy as np, stokesian, sys
n = int(sys.argv[1]) if len(sys.argv) > 1 else 10000
phi = 0.2
L = (n * 4.0 / 3.0 * np.pi / phi) ** (1.0 / 3.0)
rng = np.random.default_rng(5)
m = int(np.ceil(n ** (1 / 3)))
g = (np.arange(m) + 0.5) * L / m
X, Y, Z = np.meshgrid(g, g, g, indexing="ij")
x = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])[:n]
x = x + (rng.random(x.shape) - 0.5) * 0.3 * (L / m - 2.05)
s = stokesian.System(x, 1.0, confinement="free", box=(L, L, L), periodic_tolerance=1e-6)
for moments in sys.argv[2:] or ["F", "FTS"]:
    k = {"F": 3, "FT": 6, "FTS": 11}[moments]
    f = rng.standard_normal(k * n)
    s.apply(moments, f)
    ts = []
    for _ in range(2):
        t = time.perf_counter(); s.apply(moments, f); ts.append(time.perf_counter() - t)
    print(f"{moments} N={n} L={L:.1f}: {min(ts):.3f} s", flush=True)

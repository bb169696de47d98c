"""Time the fast product F of a periodic slit and of a periodic wall (docs/periodic.md).

A monolayer of unit spheres on a jittered square lattice at area fraction 0.3, heights
1.5 to 3.5, in a slit of gap 5 (walls at 0 and 5) and above one wall; best of 3 products.
Usage: python docs/examples/periodic_slit_product_timing.py [N ...]
"""
import time, numpy as np, stokesian, sys
for n in [int(v) for v in sys.argv[1:]] or (1000,):
    phi = 0.3
    L = np.sqrt(n * np.pi / phi)
    m = int(np.ceil(np.sqrt(n)))
    rng = np.random.default_rng(3)
    g = (np.arange(m) + 0.5) * L / m
    X, Y = np.meshgrid(g, g)
    pts = np.column_stack([X.ravel(), Y.ravel()])[:n]
    pts = pts + (rng.random(pts.shape) - 0.5) * 0.3 * (L / m - 2.05)
    z = 1.5 + 2.0 * rng.random(n)
    x = np.column_stack([pts, z])
    f = rng.standard_normal(3 * n)
    for tol in (1e-6, 1e-10):
        per = stokesian.System(x, 1.0, confinement="wall", box=(L, L), periodic_tolerance=tol)
        slit = stokesian.System(x, 1.0, confinement="slit", gap=5.0, box=(L, L), periodic_tolerance=tol)
        for name, s in (("periodic wall", per), ("periodic slit", slit)):
            s.apply("F", f)
            ts = []
            for _ in range(3):
                t = time.perf_counter(); s.apply("F", f); ts.append(time.perf_counter() - t)
            print(f"{name} F N={n} tol={tol:g}: {min(ts):.3f} s", flush=True)

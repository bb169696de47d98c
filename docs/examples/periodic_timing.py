"""Time the dense periodic mobility (docs/periodic.md): random spheres of radius 1 at
volume fraction about 0.16 in a cubic box, F and FT, two tolerances.

Run with the module built (`cargo xtask test` builds it into target/python-venv):
    target/python-venv/bin/python docs/examples/periodic_timing.py
"""
import time, numpy as np, stokesian
rng = np.random.default_rng(1)
for n, L in [(100, 30.0), (400, 48.0)]:
    pts = []
    while len(pts) < n:
        x = rng.random(3) * L
        ok = True
        for q in pts:
            d = x - q; d -= L * np.round(d / L)
            if np.linalg.norm(d) < 2.05: ok = False; break
        if ok: pts.append(x)
    x = np.array(pts)
    for tol in (1e-6, 1e-10):
        s = stokesian.System(x, 1.0, confinement="free", box=(L, L, L), periodic_tolerance=tol)
        for mom in ("F", "FT"):
            t = time.perf_counter(); m = s.mobility(mom); t = time.perf_counter() - t
            print(f"N={n} L={L} tol={tol:g} {mom}: dense {t:.3f} s")

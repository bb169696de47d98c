"""Time the dense mobility of spheres above a wall in a box periodic along it, and
between two walls (a slit of gap 5) periodic along them (docs/periodic.md): a monolayer
of spheres of radius 1 at area fraction about 0.3, centres at heights 1.5 to 3.5 above
the (lower) wall, two tolerances; the sizes and truncations as arguments (default: 100
and 400 spheres, F and FT).

Run with the module built (`cargo xtask test` builds it into target/python-venv):
    target/python-venv/bin/python docs/examples/periodic_wall_timing.py [N ...] [F|FT|FTS ...]
"""
import sys, time, numpy as np, stokesian
sizes = [int(a) for a in sys.argv[1:] if a.isdigit()] or [100, 400]
truncations = [a for a in sys.argv[1:] if a in ("F", "FT", "FTS")] or ["F", "FT"]
rng = np.random.default_rng(1)
for n in sizes:
    L = np.sqrt(n * np.pi / 0.3)
    pts = []
    while len(pts) < n:
        x = np.array([rng.random() * L, rng.random() * L, 1.5 + 2.0 * rng.random()])
        ok = True
        for q in pts:
            d = x - q; d[:2] -= L * np.round(d[:2] / L)
            if np.linalg.norm(d) < 2.05: ok = False; break
        if ok: pts.append(x)
    x = np.array(pts)
    for conf, extra in (("wall", {}), ("slit", {"gap": 5.0})):
        for tol in (1e-6, 1e-10):
            s = stokesian.System(x, 1.0, confinement=conf, box=(L, L), periodic_tolerance=tol,
                                 **extra)
            for mom in truncations:
                t = time.perf_counter(); m = s.mobility(mom); t = time.perf_counter() - t
                print(f"{conf} N={n} L={L:.1f} tol={tol:g} {mom}: dense {t:.3f} s")

"""stokesian.System: the solver from NumPy, against the command line (which reads and
writes files through the same library) bit for bit, and its errors."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import stokesian
from conftest import read_csv, wall_configuration, write_forces, write_particles

CONFINEMENTS = [
    ("free", dict(confinement="free"), ["--confinement", "free"]),
    ("wall", dict(confinement="wall", boundary_height=0.25),
     ["--confinement", "wall", "--boundary-height", "0.25"]),
    ("free_surface", dict(confinement="free_surface"), ["--confinement", "free-surface"]),
    ("interface", dict(confinement="interface", lam=0.3),
     ["--confinement", "interface", "--lambda", "0.3"]),
    ("slit", dict(confinement="slit", gap=40.0), ["--confinement", "slit", "--gap", "40"]),
]


@pytest.mark.parametrize("name,kwargs,flags", CONFINEMENTS)
@pytest.mark.parametrize("moments", ["F", "FT", "FTS"])
def test_mobility_equals_cli_bit_for_bit(tmp_path, cli, name, kwargs, flags, moments):
    positions, _, _ = wall_configuration(5)
    radii = np.array([1.0, 0.8, 1.2, 1.0, 0.9])
    s = stokesian.System(positions, radii, viscosity=1.3, **kwargs)
    assert s.confinement == name and len(s) == 5
    m = s.mobility(moments)
    k = {"F": 3, "FT": 6, "FTS": 11}[moments]
    assert m.shape == (5 * k, 5 * k)
    p = write_particles(tmp_path / "p.csv", positions, radii)
    cli("mobility", *flags, "--moments", moments, "--viscosity", "1.3", "--particles", p,
        "--out", tmp_path / "m.npy")
    assert np.array_equal(m, np.load(tmp_path / "m.npy"))
    # symmetric positive definite (the slit is wide enough here)
    assert np.allclose(m, m.T, rtol=0, atol=1e-14 * np.abs(m).max())
    np.linalg.cholesky(m)


@pytest.mark.parametrize("moments", ["F", "FT", "FTS"])
def test_apply_equals_mobility_times_x(moments):
    positions, _, _ = wall_configuration(6)
    s = stokesian.System(positions, 1.0)
    k = {"F": 3, "FT": 6, "FTS": 11}[moments]
    x = np.random.default_rng(2).normal(size=6 * k)
    got = s.apply(moments, x)
    want = s.mobility(moments) @ x
    # tiled sums against a dense product: round-off of sums of 6 terms
    assert np.linalg.norm(got - want) <= 1e-13 * np.linalg.norm(want)


@pytest.mark.parametrize("moments", ["F", "FT"])
def test_fast_product_within_its_tolerance(moments):
    # 900 spheres on a jittered lattice above the wall, heights 1.5 to 4.5
    rng = np.random.default_rng(5)
    g = np.stack(np.meshgrid(np.arange(30.0), np.arange(30.0)), -1).reshape(-1, 2) * 3.5
    positions = np.column_stack([g + rng.uniform(-0.6, 0.6, g.shape), rng.uniform(1.5, 4.5, len(g))])
    s = stokesian.System(positions, 1.0)
    k = {"F": 3, "FT": 6}[moments]
    x = rng.normal(size=len(g) * k)
    direct = s.apply(moments, x)
    for eps in (1e-3, 1e-6):
        fast = s.apply(moments, x, fmm=eps)
        assert np.linalg.norm(fast - direct) <= eps * np.linalg.norm(direct)
    forces = x[: 3 * len(g)].reshape(-1, 3)
    torques = x[3 * len(g):].reshape(-1, 3) if moments == "FT" else None
    u, w = s.velocities(forces, torques, fmm=1e-6)
    assert np.array_equal(u.ravel(), s.apply(moments, x, fmm=1e-6)[: 3 * len(g)])
    with pytest.raises(ValueError, match="1e-10"):
        s.apply(moments, x, fmm=1e-2)
    with pytest.raises(ValueError, match="FTS"):
        s.apply("FTS", np.zeros(11 * len(g)), fmm=1e-6)
    # Brownian dynamics with Lanczos noise from the fast product: runs, and needs lanczos
    few = stokesian.System(positions[:300], 1.0)
    frames = few.brownian(1, 1e-4, weight=1.0, lanczos=1e-5, fmm=1e-7)
    assert frames.shape == (2, 300, 3) and np.all(np.isfinite(frames))
    with pytest.raises(ValueError, match="lanczos"):
        s.brownian(1, 1e-4, fmm=1e-6)


@pytest.mark.parametrize("moments", ["F", "FT", "FTS"])
def test_single_precision_apply_in_si_units(moments):
    # radii of 1 um in water, pN forces: the f32 lanes run in their own units
    positions, _, _ = wall_configuration(6)
    s = stokesian.System(positions * 1e-6, 1e-6, viscosity=1e-3)
    k = {"F": 3, "FT": 6, "FTS": 11}[moments]
    x = np.random.default_rng(3).normal(size=6 * k) * 1e-12
    want = s.apply(moments, x)
    got = s.apply(moments, x, precision="single")
    # f32 lanes: 2e-6 of the norm (tests/tests/integration/lanes/single_precision.rs), per part since
    # velocities and rotation rates differ by 1e6 in these units
    for part in (slice(0, 18), slice(18, None)):
        if want[part].size:
            assert np.linalg.norm(got[part] - want[part]) <= 2e-6 * np.linalg.norm(want[part])
    with pytest.raises(ValueError, match="precision"):
        s.apply(moments, x, precision="half")


@pytest.mark.parametrize("moments,lubrication", [("F", False), ("FT", False), ("FTS", False),
                                                 ("FT", True), ("FTS", True)])
def test_velocities_equal_cli_bit_for_bit(tmp_path, cli, moments, lubrication):
    positions, forces, torques = wall_configuration(4)
    positions[1] = positions[0] + np.array([2.05, 0.0, 0.0])  # a pair near contact
    s = stokesian.System(positions, 1.0)
    strain = np.array([0.1, -0.2, 0.05, 0.3, 0.0]) if moments == "FTS" else None
    t = torques if moments != "F" else None
    u, w = s.velocities(forces, t, strain=strain, lubrication=lubrication)
    p = write_particles(tmp_path / "p.csv", positions, 1.0)
    f = write_forces(tmp_path / "f.csv", forces, t)
    extra = ["--lubrication"] if lubrication else []
    if strain is not None:
        extra += ["--strain", ",".join(repr(float(v)) for v in strain)]
    cli("velocity", "--confinement", "wall", "--moments", moments, "--particles", p,
        "--forces", f, "--out", tmp_path / "u.csv", *extra)
    want = read_csv(tmp_path / "u.csv")
    assert np.array_equal(u, want[:, :3])
    if moments == "F":
        assert w is None
    else:
        assert np.array_equal(w, want[:, 3:])


def test_strain_as_cartesian_tensor_equals_the_basis_components():
    positions, forces, torques = wall_configuration(3)
    s = stokesian.System(positions, 1.0)
    e = np.array([[0.1, 0.2, 0.0], [0.2, -0.3, 0.05], [0.0, 0.05, 0.2]])
    r2, r6 = np.sqrt(2), np.sqrt(6)
    basis = [
        np.array([[0, 1, 0], [1, 0, 0], [0, 0, 0]]) / r2,
        np.array([[0, 0, 1], [0, 0, 0], [1, 0, 0]]) / r2,
        np.array([[0, 0, 0], [0, 0, 1], [0, 1, 0]]) / r2,
        np.array([[1, 0, 0], [0, -1, 0], [0, 0, 0]]) / r2,
        np.array([[-1, 0, 0], [0, -1, 0], [0, 0, 2]]) / r6,
    ]
    comps = np.array([np.sum(b * e) for b in basis])
    u1, w1 = s.velocities(forces, torques, strain=e)
    u2, w2 = s.velocities(forces, torques, strain=comps)
    assert np.allclose(u1, u2, rtol=1e-14, atol=1e-16)
    assert np.allclose(w1, w2, rtol=1e-14, atol=1e-16)


@pytest.mark.parametrize("moments", ["FT", "FTS"])
def test_resistance_equals_cli_bit_for_bit(tmp_path, cli, moments):
    positions, _, _ = wall_configuration(4)
    positions[1] = positions[0] + np.array([2.1, 0.0, 0.0])
    s = stokesian.System(positions, 1.0)
    r = s.resistance(moments)
    p = write_particles(tmp_path / "p.csv", positions, 1.0)
    cli("resistance", "--confinement", "wall", "--moments", moments, "--particles", p,
        "--out", tmp_path / "r.npy")
    assert np.array_equal(r, np.load(tmp_path / "r.npy"))
    # without lubrication: the inverse of the far-field mobility (to the round-off of
    # inverting a matrix of condition ~1e2)
    r0 = s.resistance(moments, lubrication=False)
    assert np.allclose(r0 @ s.mobility(moments), np.eye(len(r0)), rtol=0, atol=1e-12)


def test_pair_tolerance_equals_cli_bit_for_bit(tmp_path, cli):
    positions = np.array([[0.0, 0.0, 1.6], [2.4, 0.2, 1.4], [-0.3, 2.5, 2.2]])
    s = stokesian.System(positions, 1.0)
    p = write_particles(tmp_path / "p.csv", positions, 1.0)
    got = {}
    for tol in ["0", "1e-3", "inf"]:
        got[tol] = s.resistance("FT", pair_tolerance=float(tol))
        cli("resistance", "--confinement", "wall", "--moments", "FT", "--particles", p,
            "--pair-tolerance", tol, "--out", tmp_path / "r.npy")
        assert np.array_equal(got[tol], np.load(tmp_path / "r.npy"))
    # the default is 1e-6; the closest pair (s' = 2.42) is corrected at 1e-3, not at inf
    assert np.array_equal(s.resistance("FT"), s.resistance("FT", pair_tolerance=1e-6))
    assert np.linalg.norm(got["1e-3"] - got["inf"]) > 1e-3 * np.linalg.norm(got["inf"])
    forces = np.array([[0.0, 0.0, -1.0], [0.5, 0.0, 0.0], [0.0, 0.2, 0.0]])
    u, _ = s.velocities(forces, lubrication=True, pair_tolerance=1e-3)
    cli("velocity", "--confinement", "wall", "--moments", "FT", "--particles", p,
        "--forces", write_forces(tmp_path / "f.csv", forces, np.zeros((3, 3))),
        "--lubrication", "--pair-tolerance", "1e-3", "--out", tmp_path / "u.csv")
    assert np.array_equal(u, read_csv(tmp_path / "u.csv")[:, :3])
    for bad in [-1.0, float("nan")]:
        with pytest.raises(ValueError, match="pair tolerance is .*: it must be a number >= 0"):
            s.resistance("FT", pair_tolerance=bad)
        with pytest.raises(ValueError, match="pair tolerance"):
            s.brownian(1, 1e-3, lubrication=True, pair_tolerance=bad)
    with pytest.raises(ValueError, match="with lubrication=True only"):
        s.resistance("FT", lubrication=False, pair_tolerance=1e-3)
    with pytest.raises(ValueError, match="with lubrication=True only"):
        s.velocities(forces, pair_tolerance=1e-3)


@pytest.mark.parametrize(
    "moments,options,flags",
    [
        ("F", dict(weight=0.5, repulsion_strength=2.0, debye_length=0.2),
         ["--weight", "0.5", "--repulsion-strength", "2", "--debye-length", "0.2"]),
        ("FT", dict(torque=[0.0, 0.3, 0.0], trap=0.1, every=2),
         ["--torque", "0,0.3,0", "--trap", "0.1", "--every", "2"]),
        ("F", dict(scheme="fixman", weight=0.2), ["--scheme", "fixman", "--weight", "0.2"]),
        ("F", dict(lanczos=1e-8), ["--lanczos", "1e-8"]),
        ("F", dict(lubrication=True, weight=0.3), ["--lubrication", "--weight", "0.3"]),
    ],
)
def test_brownian_equals_cli_bit_for_bit(tmp_path, cli, moments, options, flags):
    positions = np.array([[0.0, 0.0, 1.6], [2.4, 0.2, 1.4], [-0.3, 2.5, 2.2]])
    s = stokesian.System(positions, 1.0)
    traj = s.brownian(10, 1e-3, 1.0, 42, moments=moments, **options)
    every = options.get("every", 1)
    assert traj.shape == (10 // every + 1, 3, 7 if moments == "FT" else 3)
    assert np.array_equal(traj[0, :, :3], positions)
    p = write_particles(tmp_path / "p.csv", positions, 1.0)
    cli("brownian", "--confinement", "wall", "--moments", moments, "--particles", p,
        "--steps", "10", "--dt", "1e-3", "--kt", "1", "--seed", "42", *flags,
        "--out", tmp_path / "t.npy")
    assert np.array_equal(traj, np.load(tmp_path / "t.npy"))


def test_divergence_is_the_nbody_divm():
    positions, _, _ = wall_configuration(4)
    s = stokesian.System(positions, 1.0)
    nb = stokesian.NBody("open", "open", "single_wall")
    nb.setParameters(wallHeight=0.0)
    nb.initialize(1.0, 1.0, includeAngular=True)
    nb.setPositions(positions)
    lin, ang = nb.divM()
    d = s.divergence("FT")
    assert np.array_equal(d, np.concatenate([lin.ravel(), ang.ravel()]))
    assert np.array_equal(s.divergence("F"), lin.ravel())


def test_zero_copy_reads_of_contiguous_arrays_do_not_change_them():
    positions, forces, _ = wall_configuration(4)
    keep = positions.copy()
    s = stokesian.System(positions, 1.0)
    s.velocities(forces)
    assert np.array_equal(positions, keep)
    assert np.array_equal(s.positions, keep)
    assert np.array_equal(s.radii, np.ones(4))


# ---- errors: ValueError with the library's message ----------------------------------


def test_bad_systems_raise_value_error(tmp_path, cli):
    ok = np.array([[0.0, 0.0, 2.0], [3.0, 0.0, 2.0]])
    with pytest.raises(ValueError, match="unknown confinement `moon`"):
        stokesian.System(ok, 1.0, confinement="moon")
    with pytest.raises(ValueError, match="needs the parameter `lambda`.* or lam="):
        stokesian.System(ok, 1.0, confinement="interface")
    with pytest.raises(ValueError, match="needs the parameter `gap`"):
        stokesian.System(ok, 1.0, confinement="slit")
    with pytest.raises(ValueError, match="gap: `wall` has no parameter `gap`"):
        stokesian.System(ok, 1.0, confinement="wall", gap=3.0)
    with pytest.raises(ValueError, match="boundary_height: `free` has no parameters"):
        stokesian.System(ok, 1.0, confinement="free", boundary_height=1.0)
    with pytest.raises(ValueError, match="lambda = -1"):
        stokesian.System(ok, 1.0, confinement="interface", lam=-1.0)
    with pytest.raises(ValueError, match="viscosity"):
        stokesian.System(ok, 1.0, viscosity=-1.0)
    with pytest.raises(ValueError, match="radii"):
        stokesian.System(ok, [1.0, 1.0, 1.0])
    with pytest.raises(ValueError, match="shape"):
        stokesian.System(np.zeros((2, 4)), 1.0)
    with pytest.raises(ValueError, match="no particles"):
        stokesian.System(np.zeros((0, 3)), 1.0)
    # the same message as the command line for the library's errors
    for x, r in [(np.array([[0.0, 0.0, 2.0], [1.0, 0.0, 2.0]]), 1.0),
                 (np.array([[0.0, 0.0, -2.0]]), 1.0),
                 (np.array([[0.0, 0.0, 2.0]]), -0.5),
                 (np.array([[0.0, np.inf, 2.0]]), 1.0)]:
        with pytest.raises(ValueError) as e:
            stokesian.System(x, r)
        p = write_particles(tmp_path / "p.csv", x, r)
        out = cli("mobility", "--confinement", "wall", "--moments", "F", "--particles", p, "--out",
                  tmp_path / "m.npy", ok=False)
        reason = str(e.value).split(": ", 1)[1].split(" < ")[0].split(" (")[0]
        assert out.returncode != 0 and reason in out.stderr, (str(e.value), out.stderr)
    # overlaps accepted on request
    stokesian.System(np.array([[0.0, 0.0, 2.0], [1.0, 0.0, 2.0]]), 1.0, allow_overlap=True)


def test_bad_calls_raise_value_error():
    positions, forces, torques = wall_configuration(3)
    s = stokesian.System(positions, 1.0)
    with pytest.raises(ValueError, match="moments"):
        s.mobility("FTSX")
    with pytest.raises(ValueError, match="needs 9"):
        s.apply("F", np.ones(8))
    with pytest.raises(ValueError, match="rows for 3 particles"):
        s.velocities(np.ones((4, 3)))
    with pytest.raises(ValueError, match="not a finite number"):
        s.velocities(np.full((3, 3), np.nan))
    with pytest.raises(ValueError, match="symmetric and traceless"):
        s.velocities(forces, torques, strain=np.eye(3))
    with pytest.raises(ValueError, match="lubrication needs torques"):
        s.resistance("F")
    with pytest.raises(ValueError, match="dt = 0"):
        s.brownian(3, 0.0, 1.0, 0)
    with pytest.raises(ValueError, match="kt = -1"):
        s.brownian(3, 1e-3, -1.0, 0)
    with pytest.raises(ValueError, match="every"):
        s.brownian(3, 1e-3, 1.0, 0, every=0)
    with pytest.raises(ValueError, match="FTS Brownian dynamics is not implemented"):
        s.brownian(3, 1e-3, 1.0, 0, moments="FTS")
    with pytest.raises(ValueError, match="external torque at the F level"):
        s.brownian(3, 1e-3, 1.0, 0, torque=[0.0, 0.0, 1.0])
    with pytest.raises(ValueError, match="scheme"):
        s.brownian(3, 1e-3, 1.0, 0, scheme="leapfrog")
    with pytest.raises(ValueError, match="Fixman"):
        s.brownian(3, 1e-3, 1.0, 0, scheme="fixman", drift=False)
    # steps so large that every one is rejected
    with pytest.raises(ValueError, match="rejected steps, more than max_rejections = 5"):
        s.brownian(3, 10.0, 1.0, 0, weight=100.0, max_rejections=5)


def test_not_positive_definite_raises_value_error():
    # a sphere near a wall of a narrow slit: the superposed images are not positive
    # definite (docs/verification.md), so the far-field mobility cannot be inverted
    s = stokesian.System(np.array([[0.0, 0.0, 1.05]]), 1.0, confinement="slit", gap=3.0)
    assert np.linalg.eigvalsh(s.mobility("FT")).min() < 0
    with pytest.raises(ValueError, match="not positive definite"):
        s.resistance("FT")
    with pytest.raises(ValueError, match="not positive definite"):
        s.brownian(2, 1e-4, 1.0, 0)


def test_the_example_runs_without_matplotlib(tmp_path):
    example = Path(__file__).resolve().parents[1] / "examples" / "sedimentation.py"
    p = subprocess.run([sys.executable, str(example), "--steps", "20", "--no-plot"],
                       capture_output=True, text=True, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert "mean height" in p.stdout


def test_long_calls_release_the_gil():
    # A Brownian run of about a second in a thread while this thread keeps time: with the GIL
    # held for the call this thread would stand still for its whole length; released, it
    # is only ever held up for the interpreter's switch interval (5 ms) and scheduling
    # (tens of ms on a loaded machine). Pass: the longest stall is under a quarter of the
    # call.
    import threading
    import time

    rng = np.random.default_rng(0)
    grid = np.array([(i % 8, i // 8) for i in range(48)], dtype=float) * 3.0
    x = np.column_stack([grid + rng.uniform(-0.2, 0.2, grid.shape), rng.uniform(2, 4, 48)])
    s = stokesian.System(x, 1.0)
    started, done, span = threading.Event(), threading.Event(), []

    def work():
        started.set()
        t = time.perf_counter()
        s.brownian(1500, 1e-5, 1.0, 0)
        span.append(time.perf_counter() - t)
        done.set()

    worker = threading.Thread(target=work)
    worker.start()
    started.wait()
    last, stall = time.perf_counter(), 0.0
    while not done.is_set():
        now = time.perf_counter()
        stall = max(stall, now - last)
        last = now
    worker.join()
    assert span[0] > 0.2, f"the call took {span[0]:.3f} s: too short to tell"
    assert stall < span[0] / 4, f"stalled {stall:.3f} s during a {span[0]:.3f} s call"


def test_overlap_options():
    # two overlapping spheres, the second cutting the wall
    x = np.array([[0.0, 0.0, 2.0], [1.0, 0.0, 0.7]])
    with pytest.raises(ValueError, match="overlap"):
        stokesian.System(x, 1.0)
    apart = np.array([[0.0, 0.0, 2.0], [3.0, 0.0, 1.5]])
    refuse = stokesian.System(apart, 1.0, overlap="refuse")
    same = stokesian.System(apart, 1.0, overlap="rpy")
    # nothing overlaps: the same bits
    assert np.array_equal(refuse.mobility("FTS"), same.mobility("FTS"))
    far = stokesian.System(x, 1.0, allow_overlap=True)
    assert np.array_equal(far.mobility("FT"), stokesian.System(x, 1.0, overlap="far").mobility("FT"))
    rpy = stokesian.System(x, 1.0, overlap="rpy")
    for moments in ("F", "FT"):
        m = rpy.mobility(moments)
        assert np.abs(m - m.T).max() <= 1e-14 * np.abs(m).max()
        assert np.linalg.eigvalsh(m).min() > 0.0
        v = np.linspace(-1.0, 1.0, m.shape[0])
        # the tiled product and the dense matrix sum in other orders
        assert np.abs(rpy.apply(moments, v) - m @ v).max() <= 1e-13 * np.abs(m @ v).max()
    with pytest.raises(ValueError, match="not the stresslets"):
        rpy.mobility("FTS")
    with pytest.raises(ValueError, match="not the stresslets"):
        rpy.apply("FTS", np.zeros(22))
    # the drift of the damped mobility: finite (checked against differences of the
    # damped mobility in test_nbody and the Rust tests)
    assert np.all(np.isfinite(rpy.divergence("FT")))
    with pytest.raises(ValueError, match="give one of them"):
        stokesian.System(x, 1.0, allow_overlap=True, overlap="rpy")
    with pytest.raises(ValueError, match="expected"):
        stokesian.System(x, 1.0, overlap="soft")


def test_a_periodic_slit():
    # between walls at z = 0 and z = 2 in a wide square box: a small sphere on the
    # mid-plane has Faxen's mobility 1 - 1.004 a/l (l = 1, the distance to each wall),
    # which only the slit's exact Green's function gives (superposed images: 9/8); the
    # box adds O(a H/L^2)
    a = 1e-3
    s = stokesian.System(np.array([[0.3, 0.1, 1.0]]), a, confinement="slit",
                         boundary_height=0.0, gap=2.0, box=(120.0, 120.0))
    m = s.mobility("F")
    assert abs((1.0 - m[0, 0] * 6.0 * np.pi * a) / a - 1.004) < 1e-3
    # two spheres: symmetric positive definite, the (fast) product is the matrix's to the
    # default tolerance 1e-10 of the largest entry, the drift along the normal is not zero
    # off the mid-plane
    two = stokesian.System(np.array([[0.0, 0.0, 1.5], [3.0, 1.0, 3.2]]), [1.0, 0.7],
                           confinement="slit", boundary_height=0.0, gap=5.0, box=(8.0, 9.0))
    m = two.mobility("FT")
    assert np.allclose(m, m.T, rtol=0.0, atol=1e-14) and np.linalg.eigvalsh(m).min() > 0.0
    f = np.arange(12.0) / 12.0
    want = m @ f
    assert np.abs(two.apply("FT", f) - want).max() <= 1e-10 * np.abs(want).max()
    assert abs(two.divergence("F")[2]) > 1e-3
    with pytest.raises(ValueError, match="overlaps the boundary"):
        stokesian.System(np.array([[0.0, 0.0, 4.5]]), 1.0, confinement="slit",
                         boundary_height=0.0, gap=5.0, box=(8.0, 9.0))


def test_a_triply_periodic_box():
    # one sphere in a cubic box: Hasimoto's self mobility 1 - 2.8372974794806 a/L
    # + (4 pi/3)(a/L)^3 (times 1/(6 pi eta a)), to the sums' 1e-10 and the printed
    # coefficient's 1e-13
    L = 10.0
    s = stokesian.System(np.array([[1.0, 2.0, 3.0]]), 1.0, confinement="free", box=(L, L, L))
    x = 1.0 / L
    want = 1.0 - 2.8372974794806 * x + 4.0 * np.pi / 3.0 * x**3
    m = s.mobility("F")
    assert abs(m[0, 0] * 6.0 * np.pi - want) < 1e-9
    assert np.all(s.divergence("FT") == 0.0)
    two = stokesian.System(np.array([[0.0, 0.0, 0.0], [3.0, 1.0, 2.0]]), [1.0, 0.7],
                           confinement="free", box=(8.0, 9.0, 10.0), periodic_tolerance=1e-12)
    m = two.mobility("FT")
    assert np.array_equal(m, m.T) and np.linalg.eigvalsh(m).min() > 0.0
    with pytest.raises(ValueError, match="three lengths"):
        stokesian.System(np.array([[1.0, 2.0, 3.0]]), 1.0, confinement="free", box=(L,))
    with pytest.raises(ValueError, match="net lateral force"):
        stokesian.System(np.array([[1.0, 2.0, 3.0]]), 1.0, confinement="free", box=(L, L))
    with pytest.raises(ValueError, match="free surface"):
        stokesian.System(np.array([[1.0, 2.0, 3.0]]), 1.0, confinement="free_surface",
                         box=(L, L, L))
    with pytest.raises(ValueError, match="own periodic image"):
        stokesian.System(np.array([[1.0, 2.0, 3.0]]), 1.0, confinement="free",
                         box=(1.5, L, L))
    # the stresslets too (symmetric positive definite), and their lubricated resistance
    fts = two.mobility("FTS")
    assert np.array_equal(fts, fts.T) and np.linalg.eigvalsh(fts).min() > 0.0
    rs = two.resistance("FTS")
    assert np.array_equal(rs, rs.T) and np.linalg.eigvalsh(rs).min() > 0.0
    # the resistance with lubrication in the box: every image within the pair window
    r = two.resistance("FT")
    assert np.array_equal(r, r.T) and np.linalg.eigvalsh(r).min() > 0.0
    assert np.abs(r - np.linalg.inv(m)).max() > 1e-6 * np.abs(r).max()
    # Brownian dynamics in the box: frames of the unwrapped positions; no trap
    frames = two.brownian(5, 0.01, seed=1)
    assert frames.shape == (6, 2, 3) and np.all(np.isfinite(frames))
    with pytest.raises(ValueError, match="harmonic trap"):
        two.brownian(5, 0.01, trap=1.0)


def test_a_box_periodic_along_a_wall():
    # two spheres above a wall, box=(Lx, Ly): symmetric positive definite; a sphere moved
    # by Lx is the same system (to the rounding of the images' order); far apart in a
    # large box, the self block tends to the open wall's
    x = np.array([[0.0, 0.0, 2.0], [3.0, 1.0, 3.5]])
    s = stokesian.System(x, [1.0, 0.7], confinement="wall", box=(8.0, 9.0))
    m = s.mobility("FT")
    assert np.array_equal(m, m.T) and np.linalg.eigvalsh(m).min() > 0.0
    moved = x.copy()
    moved[1, 0] += 8.0
    m2 = stokesian.System(moved, [1.0, 0.7], confinement="wall", box=(8.0, 9.0)).mobility("FT")
    assert np.abs(m2 - m).max() < 1e-13 * np.abs(m).max()
    one = np.array([[0.0, 0.0, 2.0]])
    open_ = stokesian.System(one, 1.0, confinement="wall").mobility("F")
    big = stokesian.System(one, 1.0, confinement="wall", box=(400.0, 400.0)).mobility("F")
    assert np.abs(big - open_).max() < 1e-5 * np.abs(open_).max()
    with pytest.raises(ValueError, match="wall with three lengths"):
        stokesian.System(one, 1.0, confinement="wall", box=(8.0, 9.0, 10.0))
    # Brownian dynamics with the generated drift: along the normal, and in a large box the
    # open wall's (the lattice's correction to the normal self mobility falls faster than
    # the lateral one's 6 h^2 S3 / L^3)
    frames = s.brownian(5, 0.01, seed=1)
    assert frames.shape == (6, 2, 3) and np.all(np.isfinite(frames))
    d = s.divergence("F")
    assert np.abs(d[2::3]).min() > 1e-3 and np.abs(d).max() == np.abs(d[2::3]).max()
    d_open = stokesian.System(one, 1.0, confinement="wall").divergence("F")
    d_big = stokesian.System(one, 1.0, confinement="wall", box=(400.0, 400.0)).divergence("F")
    assert np.abs(d_big - d_open).max() < 1e-5 * np.abs(d_open).max()

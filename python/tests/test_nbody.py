"""stokesian.NBody: libMobility's interface, checked against the library, the command line,
closed forms from the literature, finite differences and statistics."""

import math

import numpy as np
import pytest

import stokesian
from conftest import read_csv, wall_configuration, write_forces, write_particles


def solver(positions, wall=True, angular=False, seed=7, radius=1.0, eta=1.0, tol=1e-4):
    s = stokesian.NBody("open", "open", "single_wall" if wall else "open")
    s.setParameters(wallHeight=0.0)
    s.initialize(viscosity=eta, hydrodynamicRadius=radius, includeAngular=angular,
                 tolerance=tol, seed=seed)
    s.setPositions(positions)
    return s


def test_a_libmobility_script_runs_unchanged():
    # libMobility's usage example (docs/usage), only the import changed
    from stokesian import NBody as Solver

    numberParticles = 10
    precision = np.float32 if Solver.precision == "float" else np.float64
    solver = Solver("open", "open", "single_wall")
    solver.setParameters(algorithm="advise", Nbatch=-1, NperBatch=-1, wallHeight=0.0)
    solver.initialize(viscosity=1.0, hydrodynamicRadius=1.0, includeAngular=True)
    positions, _, _ = wall_configuration(numberParticles)
    positions = positions.astype(precision)
    forces = np.random.default_rng(3).random((numberParticles, 3)).astype(precision)
    torques = np.random.default_rng(4).random((numberParticles, 3)).astype(precision)
    solver.setPositions(positions)
    linear, angular = solver.Mdot(forces, torques)
    noise_linear, noise_angular = solver.sqrtMdotW(prefactor=1.0)
    drift_linear, drift_angular = solver.divM(prefactor=1.0)
    vel_linear, vel_angular = solver.LangevinVelocities(dt=0.01, kbt=1.0, forces=forces,
                                                        torques=torques)
    solver.clean()
    for a in (linear, angular, noise_linear, noise_angular, drift_linear, drift_angular,
              vel_linear, vel_angular):
        assert a.shape == (numberParticles, 3) and a.dtype == np.float64
        assert np.all(np.isfinite(a))
    assert Solver.precision == "double"


@pytest.mark.parametrize("wall", [True, False])
@pytest.mark.parametrize("angular", [False, True])
def test_mdot_equals_library_and_cli_bit_for_bit(tmp_path, cli, wall, angular):
    positions, forces, torques = wall_configuration(6)
    s = solver(positions, wall=wall, angular=angular)
    lin, ang = s.Mdot(forces, torques if angular else None)
    # the library's System (same kernels, same tiled product): identical bits
    system = stokesian.System(positions, 1.0, confinement="wall" if wall else "free")
    moments = "FT" if angular else "F"
    x = np.concatenate([forces.ravel(), torques.ravel()]) if angular else forces.ravel()
    want = system.apply(moments, x)
    assert np.array_equal(lin.ravel(), want[: 3 * 6])
    # the command line, `stokesian velocity` (its CSV holds shortest round-trip numbers)
    p = write_particles(tmp_path / "p.csv", positions, 1.0)
    f = write_forces(tmp_path / "f.csv", forces, torques if angular else None)
    cli("velocity", "--confinement", "wall" if wall else "free", "--moments", moments,
        "--particles", p, "--forces", f, "--out", tmp_path / "u.csv")
    u = read_csv(tmp_path / "u.csv")
    assert np.array_equal(lin, u[:, :3])
    if angular:
        assert np.array_equal(ang, u[:, 3:])
    else:
        assert ang is None


@pytest.mark.parametrize("angular", [False, True])
def test_mdot_equals_dense_mobility_times_forces(angular):
    positions, forces, torques = wall_configuration(7)
    s = solver(positions, angular=angular)
    lin, ang = s.Mdot(forces, torques if angular else None)
    system = stokesian.System(positions, 1.0)
    if angular:
        x = np.concatenate([forces.ravel(), torques.ravel()])
        want = system.mobility("FT") @ x
        got = np.concatenate([lin.ravel(), ang.ravel()])
    else:
        want = system.mobility("F") @ forces.ravel()
        got = lin.ravel()
    # the same blocks summed in another order (tiles against a dense product): round-off
    # of a sum of 7 terms of size ~|M||x|, so 1e-13 of the norm is ample and still far
    # below any wrong block (the smallest couplings here are ~1e-3 of the norm)
    assert np.linalg.norm(got - want) <= 1e-13 * np.linalg.norm(want)


def test_free_space_pair_is_rotne_prager_yamakawa():
    # Rotne & Prager 1969, Yamakawa 1970 (r >= 2a), written out independently here:
    # self 1/(6 pi eta a); pair 1/(8 pi eta r) [(1 + 2a^2/(3r^2)) I + (1 - 2a^2/r^2) rr]
    a, eta = 0.7, 2.5
    x1, x2 = np.array([0.1, -0.2, 0.3]), np.array([1.9, 0.8, -0.6])
    s = solver(np.array([x1, x2]), wall=False, radius=a, eta=eta)
    d = x2 - x1
    r = np.linalg.norm(d)
    rr = np.outer(d, d) / r**2
    pair = ((1 + 2 * a**2 / (3 * r**2)) * np.eye(3) + (1 - 2 * a**2 / r**2) * rr) / (
        8 * math.pi * eta * r)
    self_ = np.eye(3) / (6 * math.pi * eta * a)
    m = np.zeros((6, 6))
    for j in range(6):
        e = np.zeros(6)
        e[j] = 1.0
        m[:, j] = s.Mdot(e.reshape(2, 3))[0].ravel()
    want = np.block([[self_, pair], [pair, self_]])
    # closed form in double precision against the generated kernel: round-off only
    assert np.max(np.abs(m - want)) <= 1e-15 * np.max(np.abs(want)) * 10


@pytest.mark.parametrize("h", [10.0, 30.0])
def test_wall_self_mobility_is_faxen_and_lorentz_at_large_height(h):
    # A sphere at height h above a no-slip wall, to O((a/h)^3) (Faxen 1923 parallel,
    # Lorentz 1907 normal; Happel & Brenner 1965, eqs. 7-4.39 and 7-4.28):
    # mu_par / mu0 = 1 - 9/16 (a/h) + 1/8 (a/h)^3, mu_perp / mu0 = 1 - 9/8 (a/h) + 1/2 (a/h)^3
    a = 1.0
    s = solver(np.array([[0.0, 0.0, h]]), radius=a)
    mu0 = 1 / (6 * math.pi)
    par = s.Mdot(np.array([[1.0, 0.0, 0.0]]))[0][0, 0] / mu0
    perp = s.Mdot(np.array([[0.0, 0.0, 1.0]]))[0][0, 2] / mu0
    e = a / h
    # the next terms are O(e^4) and O(e^5) (45/256 e^4 for the exact parallel series, of
    # which the Rotne-Prager-Blake mobility keeps -e^5/16; -1/8 e^5 normal): the
    # tolerance 0.2 e^4 admits them and rejects any error in the kept terms
    assert abs(par - (1 - 9 / 16 * e + e**3 / 8)) < 0.2 * e**4
    assert abs(perp - (1 - 9 / 8 * e + e**3 / 2)) < 0.2 * e**4


def mdot_at(positions, x, angular):
    s = solver(positions, angular=angular)
    n = len(positions)
    if angular:
        lin, ang = s.Mdot(x[: 3 * n].reshape(n, 3), x[3 * n:].reshape(n, 3))
        return np.concatenate([lin.ravel(), ang.ravel()])
    return s.Mdot(x.reshape(n, 3))[0].ravel()


@pytest.mark.parametrize("angular", [False, True])
def test_divm_equals_central_differences_of_mdot(angular):
    positions, _, _ = wall_configuration(3, seed=5)
    n = len(positions)
    k = 6 if angular else 3
    s = solver(positions, angular=angular)
    lin, ang = s.divM()
    got = np.concatenate([lin.ravel(), ang.ravel()]) if angular else lin.ravel()
    # div M_i = sum_j d M_ij / d x_j over the 3N positions: column j of M by Mdot of the
    # unit vector e_j, differentiated by central differences in x_j
    h = 1e-4
    want = np.zeros(k * n)
    for j in range(3 * n):
        e = np.zeros(k * n)
        e[j] = 1.0
        plus, minus = positions.copy(), positions.copy()
        plus.flat[j] += h
        minus.flat[j] -= h
        want += (mdot_at(plus, e, angular) - mdot_at(minus, e, angular)) / (2 * h)
    # central differences: truncation O(h^2 M''') ~ 1e-8 of the mobility over a length,
    # round-off O(eps M / h) ~ 1e-12; 1e-6 of the largest component is far above both and
    # far below the drift itself
    assert np.max(np.abs(got - want)) <= 1e-6 * np.max(np.abs(want))
    assert np.max(np.abs(want)) > 1e-3  # the wall makes the drift far from zero


def test_divm_is_zero_in_free_space():
    positions, _, _ = wall_configuration(4)
    lin, _ = solver(positions, wall=False).divM()
    # RPY in free space is divergence-free for non-overlapping spheres: round-off only
    assert np.max(np.abs(lin)) < 1e-15


def test_sqrtmdotw_has_covariance_m():
    positions = np.array([[0.0, 0.0, 1.3], [2.4, 0.3, 1.8]])
    s = solver(positions, angular=True, seed=11)
    samples = 20000
    draws = np.empty((samples, 12))
    for i in range(samples):
        lin, ang = s.sqrtMdotW(prefactor=1.0)
        draws[i, :6] = lin.ravel()
        draws[i, 6:] = ang.ravel()
    m = stokesian.System(positions, 1.0).mobility("FT")
    cov = draws.T @ draws / samples
    # each entry of the sample covariance of K Gaussian draws has standard error
    # sqrt((M_ii M_jj + M_ij^2) / K); |C - M| < 5 sigma for all 78 distinct entries fails
    # with probability < 78 * 5.7e-7 = 4.5e-5 if the covariance is M (the run is seeded,
    # so the outcome is fixed); the Lanczos tolerance 1e-4 biases entries by ~1e-4 M,
    # far below sigma ~ 1e-2 M
    sigma = np.sqrt((np.outer(np.diag(m), np.diag(m)) + m**2) / samples)
    z = np.abs(cov - m) / sigma
    assert z.max() < 5, f"largest deviation {z.max():.2f} sigma"
    # and the mean is zero: |mean_i| < 5 sqrt(M_ii / K)
    assert np.all(np.abs(draws.mean(axis=0)) < 5 * np.sqrt(np.diag(m) / samples))
    # prefactor scales it
    s2 = solver(positions, angular=True, seed=11)
    s3 = solver(positions, angular=True, seed=11)
    a, _ = s2.sqrtMdotW(prefactor=1.0)
    b, _ = s3.sqrtMdotW(prefactor=3.0)
    assert np.allclose(3.0 * a, b, rtol=1e-15, atol=0)


@pytest.mark.parametrize("angular", [False, True])
def test_langevin_velocities_compose_mdot_sqrtmdotw_divm(angular):
    positions, forces, torques = wall_configuration(4)
    dt, kbt = 0.01, 0.7
    t = torques if angular else None
    a = solver(positions, angular=angular, seed=3)
    b = solver(positions, angular=angular, seed=3)
    lin, ang = a.LangevinVelocities(dt, kbt, forces, t)
    m_lin, m_ang = b.Mdot(forces, t)
    w_lin, w_ang = b.sqrtMdotW(prefactor=math.sqrt(2 * kbt / dt))
    d_lin, d_ang = b.divM(prefactor=kbt)
    # the same random numbers (same seed) and the same additions in the same order:
    # identical bits
    assert np.array_equal(lin, m_lin + (w_lin + d_lin))
    if angular:
        assert np.array_equal(ang, m_ang + (w_ang + d_ang))
    else:
        assert ang is None
    # kbt = 0: the deterministic part alone
    c = solver(positions, angular=angular, seed=3)
    assert np.array_equal(c.LangevinVelocities(dt, 0.0, forces, t)[0], m_lin)


def test_shapes_n3_and_3n_give_the_same_numbers():
    positions, forces, torques = wall_configuration(5)
    a = solver(positions, angular=True, seed=2)
    b = solver(positions.ravel(), angular=True, seed=2)
    la, aa = a.Mdot(forces, torques)
    lb, ab = b.Mdot(forces.ravel(), torques.ravel())
    assert la.shape == (5, 3) and lb.shape == (15,) and ab.shape == (15,)
    assert np.array_equal(la.ravel(), lb) and np.array_equal(aa.ravel(), ab)
    wa, _ = a.sqrtMdotW()
    wb, _ = b.sqrtMdotW()
    assert wa.shape == (5, 3) and wb.shape == (15,)
    assert np.array_equal(wa.ravel(), wb)
    da, _ = a.divM()
    db, _ = b.divM()
    assert da.shape == (5, 3) and db.shape == (15,)
    assert np.array_equal(da.ravel(), db)
    # lists, integers and non-contiguous arrays are read as float64 too
    strided = np.asfortranarray(forces)
    assert np.array_equal(a.Mdot(strided)[0], a.Mdot(forces.tolist())[0])
    # radii per particle, as an array (beyond libMobility): bit for bit one radius of 1
    # (the same F kernels; the FT solver's linear part comes from other kernels, whose
    # roundings differ in the last bits)
    c = stokesian.NBody("open", "open", "single_wall")
    c.setParameters(wallHeight=0.0)
    c.initialize(1.0, np.ones(5))
    c.setPositions(positions)
    assert np.array_equal(c.Mdot(forces)[0], solver(positions).Mdot(forces)[0])
    # and the FT solver's linear part to round-off (kernels of 1e-15, report section a)
    u, v = c.Mdot(forces)[0], a.Mdot(forces)[0]
    assert np.linalg.norm(u - v) <= 1e-13 * np.linalg.norm(v)


def test_wall_height_moves_the_wall():
    positions, forces, _ = wall_configuration(3)
    a = solver(positions)
    b = stokesian.NBody("open", "open", "single_wall")
    b.setParameters(wallHeight=-2.5)
    b.initialize(viscosity=1.0, hydrodynamicRadius=1.0)
    b.setPositions(positions - np.array([0.0, 0.0, 2.5]))
    # the same configuration relative to the wall: the same mobility to round-off of
    # the shifted coordinates (2.5 is exact in binary, so the heights are too)
    assert np.allclose(a.Mdot(forces)[0], b.Mdot(forces)[0], rtol=1e-14, atol=0)


# ---- bad input: every case raises ValueError (nothing crashes) ----------------------


def test_periodic_and_two_walls_are_refused():
    for per in [("periodic", "periodic", "periodic"), ("periodic", "periodic", "open"),
                ("open", "open", "two_walls"), ("single_wall", "open", "open")]:
        with pytest.raises(ValueError, match="not implemented"):
            stokesian.NBody(*per)


def test_torques_without_include_angular():
    positions, forces, torques = wall_configuration(3)
    s = solver(positions, angular=False)
    with pytest.raises(ValueError, match="includeAngular"):
        s.Mdot(forces, torques)


def test_calls_before_set_positions_and_after_clean():
    s = stokesian.NBody("open", "open", "open")
    s.setParameters()
    with pytest.raises(ValueError, match="initialize"):
        s.setPositions(np.zeros((1, 3)))
    s.initialize(1.0, 1.0)
    for call in (lambda: s.Mdot(np.ones((1, 3))), lambda: s.sqrtMdotW(),
                 lambda: s.divM(), lambda: s.LangevinVelocities(0.1, 1.0)):
        with pytest.raises(ValueError, match="setPositions"):
            call()
    s.setPositions(np.zeros((1, 3)))
    s.Mdot(np.ones((1, 3)))
    s.clean()
    with pytest.raises(ValueError, match="setPositions"):
        s.Mdot(np.ones((1, 3)))


def test_bad_positions_and_forces(tmp_path, cli):
    s = stokesian.NBody("open", "open", "single_wall")
    s.setParameters(wallHeight=0.0)
    s.initialize(1.0, 1.0)
    cases = {
        "nan": np.array([[0.0, 0.0, 2.0], [np.nan, 0.0, 5.0]]),
        "overlap": np.array([[0.0, 0.0, 2.0], [1.5, 0.0, 2.0]]),
        "below the wall": np.array([[0.0, 0.0, 2.0], [5.0, 0.0, -1.0]]),
        "cuts the wall": np.array([[0.0, 0.0, 2.0], [5.0, 0.0, 0.5]]),
    }
    for what, x in cases.items():
        with pytest.raises(ValueError) as e:
            s.setPositions(x)
        # the command line reports the same library message (after the file and line)
        p = write_particles(tmp_path / "p.csv", x, 1.0)
        out = cli("mobility", "--confinement", "wall", "--moments", "F", "--particles", p, "--out",
                  tmp_path / "m.npy", ok=False)
        assert out.returncode != 0
        reason = str(e.value).split(": ", 1)[1]
        # the CLI adds a hint on overlaps ("(--allow-overlap accepts this)") after the
        # library's numbers: compare up to that
        assert reason.split(" < ")[0].split(" (")[0] in out.stderr, (what, reason, out.stderr)
    for bad in (np.zeros((2, 2)), np.zeros(7), np.zeros((2, 3, 1))):
        with pytest.raises(ValueError, match="shape"):
            s.setPositions(bad)
    s.setPositions(np.array([[0.0, 0.0, 2.0], [5.0, 0.0, 3.0]]))
    with pytest.raises(ValueError, match="3 rows for 2 particles"):
        s.Mdot(np.ones((3, 3)))
    with pytest.raises(ValueError, match="not a finite number"):
        s.Mdot(np.array([[1.0, np.inf, 0.0], [0.0, 0.0, 0.0]]))
    with pytest.raises(ValueError, match="forces or torques"):
        s.Mdot()
    with pytest.raises(ValueError, match="radius"):
        s.initialize(1.0, -1.0)
        s.setPositions(np.array([[0.0, 0.0, 2.0]]))
    with pytest.raises(ValueError, match="viscosity"):
        s.initialize(0.0, 1.0)
    with pytest.raises(ValueError, match="radii for"):
        s.initialize(1.0, np.ones(3))
        s.setPositions(np.array([[0.0, 0.0, 2.0], [5.0, 0.0, 3.0]]))
    with pytest.raises(ValueError, match="wallHeight"):
        stokesian.NBody("open", "open", "open").setParameters(wallHeight=1.0)
    with pytest.raises(ValueError, match="dt"):
        s.initialize(1.0, 1.0)
        s.setPositions(np.array([[0.0, 0.0, 2.0]]))
        s.LangevinVelocities(0.0, 1.0)


def test_refused_positions_leave_the_previous_ones():
    positions, forces, _ = wall_configuration(3)
    s = solver(positions)
    before = s.Mdot(forces)[0]
    bad = positions.copy()
    bad[1] = bad[0] + np.array([0.5, 0.0, 0.0])  # overlaps sphere 0
    with pytest.raises(ValueError, match="overlap"):
        s.setPositions(bad)
    assert np.array_equal(s.Mdot(forces)[0], before)

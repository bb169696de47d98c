"""stokesian.NBody: libMobility's interface, checked against the library, the command line,
closed forms from the literature, finite differences and statistics."""

import math

import numpy as np
import pytest

import stokesian
from conftest import read_csv, wall_configuration, write_forces, write_particles


def solver(positions, wall=True, angular=False, seed=7, radius=1.0, eta=1.0, tol=1e-4):
    s = stokesian.NBody("open", "open", "single_wall" if wall else "open")
    if wall:
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


@pytest.mark.parametrize("angular", [False, True])
def test_divm_is_exactly_zero_in_free_space(angular):
    positions, _, _ = wall_configuration(4)
    lin, ang = solver(positions, wall=False, angular=angular).divM()
    # free space is translation invariant and RPY incompressible: the generated pair
    # divergence is the constant 0 (kernel-gen, divergence.rs), not rounding of 1e-18
    assert np.all(lin == 0.0)
    if angular:
        assert np.all(ang == 0.0)


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


# ---- bad input: every case raises InputError (nothing crashes) ----------------------


def test_errors_are_input_errors_both_runtime_and_value_errors():
    # libMobility's users catch RuntimeError, System's users ValueError: one class is both
    assert issubclass(stokesian.InputError, RuntimeError)
    assert issubclass(stokesian.InputError, ValueError)
    positions, forces, torques = wall_configuration(3)
    s = solver(positions)
    calls = {
        "periodicity": lambda: stokesian.NBody("periodicasdas", "periodic", "open"),
        "positions shape": lambda: s.setPositions(np.zeros((3, 4))),
        "forces shape": lambda: s.Mdot(np.ones((3, 2))),
        "torques without includeAngular": lambda: s.Mdot(forces, torques),
        "algorithm": lambda: s.setParameters("quick", wallHeight=0.0),
        "before setPositions": lambda: stokesian.NBody("open", "open", "open").divM(),
        "System": lambda: stokesian.System(np.zeros((2, 3)), 1.0, confinement="free"),
    }
    for what, call in calls.items():
        with pytest.raises(stokesian.InputError):
            call()
    assert stokesian.InputError.__module__ == "stokesian"


def test_a_centre_below_the_wall_in_libmobility_words():
    s = stokesian.NBody("open", "open", "single_wall")
    s.setParameters(wallHeight=1.0)
    s.initialize(viscosity=1.0, hydrodynamicRadius=1.0)
    with pytest.raises(RuntimeError, match="fallen below the wall"):
        s.setPositions(np.array([1.0, 2.0, 0.5]))


def test_wall_height_is_required_with_a_wall_and_refused_without():
    with pytest.raises(stokesian.InputError, match="wallHeight is required"):
        stokesian.NBody("open", "open", "single_wall").setParameters("advise")
    # as libMobility: any wallHeight without a wall, 0 included
    with pytest.raises(stokesian.InputError, match="only with"):
        stokesian.NBody("open", "open", "open").setParameters(wallHeight=0.0)
    # a wall without setParameters: no height to default to
    s = stokesian.NBody("open", "open", "single_wall")
    s.initialize(1.0, 1.0)
    with pytest.raises(stokesian.InputError, match="wallHeight"):
        s.setPositions(np.array([[0.0, 0.0, 3.0]]))
    # free space needs no setParameters at all
    f = stokesian.NBody("open", "open", "open")
    f.initialize(1.0, 1.0)
    f.setPositions(np.array([[0.0, 0.0, 3.0]]))


@pytest.mark.parametrize("call", ["Mdot", "LangevinVelocities"])
def test_each_output_is_shaped_like_its_own_input(call):
    positions, forces, torques = wall_configuration(3)
    s = solver(positions, angular=True)
    run = getattr(s, call)
    args = (0.01, 0.0) if call == "LangevinVelocities" else ()
    lin, ang = run(*args, forces.ravel(), torques)
    assert lin.shape == (9,) and ang.shape == (3, 3)
    lin, ang = run(*args, forces, torques.ravel())
    assert lin.shape == (3, 3) and ang.shape == (9,)
    # one sphere, positions (3,): (1, 3) torques give (1, 3) angular velocities
    one = solver(np.array([0.0, 0.0, 2.0]), angular=True)
    lin, ang = getattr(one, call)(*args, np.ones(3), np.ones((1, 3)))
    assert lin.shape == (3,) and ang.shape == (1, 3)
    lin, ang = getattr(one, call)(*args, torques=np.ones((1, 3)))
    # no forces: Mdot shapes both like the torques, LangevinVelocities the velocities
    # like the positions (libMobility's rules)
    assert lin.shape == ((1, 3) if call == "Mdot" else (3,)) and ang.shape == (1, 3)


def batched(positions, nbatch, nper, wall=True, angular=False, seed=7):
    s = stokesian.NBody("open", "open", "single_wall" if wall else "open")
    s.setParameters(Nbatch=nbatch, NperBatch=nper, **({"wallHeight": 0.0} if wall else {}))
    s.initialize(viscosity=1.0, hydrodynamicRadius=1.0, includeAngular=angular, seed=seed)
    s.setPositions(positions)
    return s


@pytest.mark.parametrize("wall", [True, False])
@pytest.mark.parametrize("angular", [False, True])
def test_batches_do_not_interact(wall, angular):
    # three batches of 4: the first and the last in the same place (they would overlap
    # as one system), the middle one elsewhere; each batch answers as if alone
    positions, forces, torques = wall_configuration(12)
    groups = [positions[:4], positions[4:8] + np.array([0.7, -0.3, 0.4]), positions[:4]]
    together = np.concatenate(groups)
    s = batched(together, 3, 4, wall=wall, angular=angular)
    t = torques if angular else None
    lin, ang = s.Mdot(forces, t)
    dlin, dang = s.divM()
    for b, group in enumerate(groups):
        rows = slice(4 * b, 4 * b + 4)
        alone = solver(group, wall=wall, angular=angular)
        want, want_ang = alone.Mdot(forces[rows], torques[rows] if angular else None)
        # the same kernels on the same slice: identical bits
        assert np.array_equal(lin[rows], want)
        d, d_ang = alone.divM()
        assert np.array_equal(dlin[rows], d)
        if angular:
            assert np.array_equal(ang[rows], want_ang)
            assert np.array_equal(dang[rows], d_ang)
    # Nbatch alone or NperBatch alone, where they agree with the number of particles
    one = batched(together[:4], 1, -1, wall=wall)
    assert np.array_equal(one.Mdot(forces[:4])[0], solver(together[:4], wall=wall).Mdot(forces[:4])[0])


def test_batched_noise_has_block_diagonal_covariance():
    # two batches of one sphere at the same point 2 radii above the wall: M is two
    # copies of the self mobility, and the two spheres' noises are uncorrelated
    x = np.array([[0.0, 0.0, 2.0], [0.0, 0.0, 2.0]])
    s = batched(x, 2, 1, seed=5)
    samples = 10000
    draws = np.array([s.sqrtMdotW()[0].ravel() for _ in range(samples)])
    m1 = stokesian.System(x[:1], 1.0).mobility("F")
    m = np.block([[m1, np.zeros((3, 3))], [np.zeros((3, 3)), m1]])
    cov = draws.T @ draws / samples
    # standard error of each entry sqrt((M_ii M_jj + M_ij^2) / K): 5 sigma over the 21
    # distinct entries fails with probability < 21 * 5.7e-7 if the covariance is M (the
    # run is seeded, so the outcome is fixed); a coupling of the batches would put the
    # pair mobility at ~0.4 of the self terms into the off-diagonal block, ~40 sigma
    sigma = np.sqrt((np.outer(np.diag(m), np.diag(m)) + m**2) / samples)
    assert (np.abs(cov - m) / sigma).max() < 5


@pytest.mark.parametrize(("nbatch", "nper", "n"), [(5, 1, 10), (2, -1, 8), (-1, 3, 8), (0, 4, 8), (3, 3, 8)])
def test_invalid_batches_raise(nbatch, nper, n):
    # libMobility: a negative Nbatch is one batch, a negative NperBatch all particles;
    # their product must be the number of particles
    positions, _, _ = wall_configuration(n)
    with pytest.raises(stokesian.InputError, match="batch"):
        batched(positions, nbatch, nper)


class DLPackOnly:
    """An array of some other library, as NumPy sees it through DLPack alone."""

    def __init__(self, a):
        self._a = np.ascontiguousarray(a)

    def __dlpack__(self, **kwargs):
        return self._a.__dlpack__(**kwargs)


class OtherArray(DLPackOnly):
    """An array library of its own: DLPack, its device, and an array API namespace
    whose from_dlpack makes its arrays (as torch, jax and cupy do)."""

    def __dlpack_device__(self):
        return (1, 0)

    def __array_namespace__(self):
        return OtherNamespace


class OtherNamespace:
    @staticmethod
    def from_dlpack(x):
        return OtherArray(np.from_dlpack(x))


class OnTheGpu(OtherArray):
    def __dlpack_device__(self):
        return (2, 0)


@pytest.mark.parametrize("angular", [False, True])
def test_any_array_in_the_same_kind_out(angular):
    positions, forces, torques = wall_configuration(4)
    t = torques if angular else None
    want = solver(positions, angular=angular, seed=9)
    # read through DLPack alone (NumPy's from_dlpack): NumPy arrays out, same numbers
    a = solver(DLPackOnly(positions), angular=angular, seed=9)
    got = a.Mdot(DLPackOnly(forces), DLPackOnly(t) if angular else None)
    for g, w in zip(got, want.Mdot(forces, t)):
        assert (g is None) == (w is None)
        if w is not None:
            assert type(g) is np.ndarray and np.array_equal(g, w)
    # an array library with a namespace: its own arrays out, from every method
    b = solver(OtherArray(positions), angular=angular, seed=9)
    c = solver(positions, angular=angular, seed=9)
    outputs = {
        "Mdot": (b.Mdot(OtherArray(forces), OtherArray(t) if angular else None),
                 c.Mdot(forces, t)),
        "sqrtMdotW": (b.sqrtMdotW(), c.sqrtMdotW()),
        "divM": (b.divM(), c.divM()),
        "LangevinVelocities": (b.LangevinVelocities(0.01, 1.0), c.LangevinVelocities(0.01, 1.0)),
    }
    for method, (got, want) in outputs.items():
        for g, w in zip(got, want):
            if w is None:
                assert g is None, method
                continue
            assert isinstance(g, OtherArray), method
            assert np.array_equal(np.from_dlpack(g), w), method
    # arrays on another device are refused, not read
    with pytest.raises(stokesian.InputError, match="CPU"):
        c.Mdot(OnTheGpu(forces))


def test_an_array_api_library_gets_its_own_arrays_back():
    # array-api-strict (installed by `cargo xtask test` and the test extra): a real array
    # library besides NumPy, offering DLPack and an array API namespace
    import array_api_strict as xp

    positions, forces, torques = wall_configuration(3)
    s = solver(xp.asarray(positions), angular=True, seed=4)
    c = solver(positions, angular=True, seed=4)
    got = {
        "Mdot": s.Mdot(xp.asarray(forces), xp.asarray(torques)),
        "sqrtMdotW": s.sqrtMdotW(),
        "divM": s.divM(),
        "LangevinVelocities": s.LangevinVelocities(0.01, 1.0, xp.asarray(forces)),
    }
    want = {
        "Mdot": c.Mdot(forces, torques),
        "sqrtMdotW": c.sqrtMdotW(),
        "divM": c.divM(),
        "LangevinVelocities": c.LangevinVelocities(0.01, 1.0, forces),
    }
    for method, pair in got.items():
        for g, w in zip(pair, want[method]):
            assert type(g) is type(xp.asarray(positions)), method
            assert g.dtype == xp.float64 and g.shape == w.shape, method
            # the same kernels and random numbers: identical bits
            assert np.array_equal(np.from_dlpack(g), w), method


def test_doubly_periodic_and_two_walls_are_refused():
    for per in [("periodic", "periodic", "open"),
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
        "fallen below the wall": np.array([[0.0, 0.0, 2.0], [5.0, 0.0, -1.0]]),
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
        if what == "fallen below the wall":
            # libMobility's words, which its users match on, then the library's numbers
            reason = reason.split("fallen below the wall: ", 1)[1]
        # the CLI adds a hint on overlaps ("(--overlap rpy or far accepts this)", "even
        # with --overlap") after the library's words: compare up to that
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
    bad[1] = bad[0]  # the centre of sphere 0
    with pytest.raises(ValueError, match="same centre"):
        s.setPositions(bad)
    assert np.array_equal(s.Mdot(forces)[0], before)


@pytest.mark.parametrize("wall", [True, False])
@pytest.mark.parametrize("angular", [False, True])
def test_overlaps_take_the_rpy_forms_as_in_libmobility(wall, angular):
    # libMobility's NBody evaluates overlapping spheres with the RPY overlap forms (and
    # damps spheres cutting the wall): so does this one, the same as
    # System(..., overlap="rpy"), symmetric positive definite
    x = np.array([[0.0, 0.0, 2.0], [1.2, 0.0, 2.3], [0.4, 0.9, 0.6]])
    if not wall:
        x[:, 2] += 5.0
    s = solver(x, wall=wall, angular=angular)
    k = 6 if angular else 3
    conf = "wall" if wall else "free"
    m = stokesian.System(x, 1.0, confinement=conf, overlap="rpy").mobility("FT" if angular else "F")
    n = len(x)
    cols = []
    for j in range(k * n):
        e = np.zeros(k * n)
        e[j] = 1.0
        f = e[: 3 * n].reshape(n, 3)
        t = e[3 * n :].reshape(n, 3) if angular else None
        lin, ang = s.Mdot(f, t)
        cols.append(np.concatenate([lin.ravel()] + ([ang.ravel()] if angular else [])))
    got = np.array(cols).T
    # the tiled product and the dense matrix sum in other orders: 1e-13 of the largest
    assert np.abs(got - m).max() <= 1e-13 * np.abs(m).max()
    assert np.abs(m - m.T).max() <= 1e-14 * np.abs(m).max()
    assert np.linalg.eigvalsh(m).min() > 0.0
    s.divM()


@pytest.mark.parametrize("angular", [False, True])
def test_divm_of_damped_spheres_is_the_divergence_of_the_damped_mobility(angular):
    # spheres cutting the wall (damped, as libMobility's NBody damps them) and
    # overlapping each other: divM against central differences of Mdot over the
    # positions, the reference libMobility's thermal-drift test computes (its
    # deterministic_div_m). Step 1e-5: truncation ~1e-10, rounding ~1e-16/1e-5; the
    # drift is of order 1/(6 pi) here, so 1e-7 absolute.
    x = np.array([[0.0, 0.0, 0.6], [1.3, 0.2, 0.45], [0.5, 1.4, 2.2], [3.0, 0.0, 1.7]])
    s = solver(x, wall=True, angular=angular)
    lin, ang = s.divM()
    n, h = len(x), 1e-5
    want = np.zeros(6 * n if angular else 3 * n)
    for q in range(n):
        for j in range(3):
            f = np.zeros((n, 3))
            f[q, j] = 1.0
            t = np.zeros((n, 3)) if angular else None
            cols = []
            for sign in (1.0, -1.0):
                y = x.copy()
                y[q, j] += sign * h
                s.setPositions(y)
                u, w = s.Mdot(f, t)
                cols.append(np.concatenate([u.ravel()] + ([w.ravel()] if angular else [])))
            want += (cols[0] - cols[1]) / (2 * h)
    got = np.concatenate([lin.ravel()] + ([ang.ravel()] if angular else []))
    assert np.abs(want).max() > 1e-2  # the damping's terms are not small here
    assert np.abs(got - want).max() < 1e-7, np.abs(got - want).max()


def test_a_triply_periodic_box_as_libmobilitys_pse():
    # ("periodic", "periodic", "periodic") with the box through setParameters (PSE's
    # names): one sphere's self mobility is Hasimoto's, 1 - 2.8372974794806 a/L
    # + (4 pi/3)(a/L)^3 (libMobility's own PSE test checks it to 1e-6; the sums here are
    # good to 1e-10)
    L, a = 16.0, 2.0
    s = stokesian.NBody("periodic", "periodic", "periodic")
    s.setParameters(Lx=L, Ly=L, Lz=L, psi=0.5, shearStrain=0.0)
    s.initialize(viscosity=1.0, hydrodynamicRadius=a)
    s.setPositions(np.array([[1.0, 2.0, 3.0]]))
    u, _ = s.Mdot(np.array([[1.0, 0.0, 0.0]]))
    x = a / L
    want = (1.0 - 2.8372974794806 * x + 4.0 * np.pi / 3.0 * x**3) / (6.0 * np.pi * a)
    assert abs(u[0, 0] - want) < 1e-10 * want
    drift, _ = s.divM()
    assert np.all(drift == 0.0)
    with pytest.raises(RuntimeError, match="Lx, Ly and Lz are required"):
        stokesian.NBody("periodic", "periodic", "periodic").setParameters(Lx=L)
    with pytest.raises(RuntimeError, match="shearStrain"):
        s.setParameters(Lx=L, Ly=L, Lz=L, shearStrain=0.1)
    with pytest.raises(RuntimeError, match="apply only"):
        stokesian.NBody("open", "open", "open").setParameters(Lx=L, Ly=L, Lz=L)
    # in batches, a box's errors name the particles by their indices among all: the
    # second batch's spheres overlap by their nearest images (1.5 apart across z = L)
    b = stokesian.NBody("periodic", "periodic", "periodic")
    b.setParameters(Nbatch=2, NperBatch=2, Lx=L, Ly=L, Lz=L)
    b.initialize(viscosity=1.0, hydrodynamicRadius=1.0)
    with pytest.raises(ValueError, match="particles 2 and 3 overlap in the periodic box"):
        b.setPositions(np.array([[0.0, 0.0, 0.0], [5.0, 5.0, 5.0],
                                 [1.0, 1.0, 1.0], [1.0, 1.0, L - 0.5]]))


def test_periodic_between_two_walls_as_libmobilitys_dpstokes():
    # ("periodic", "periodic", "two_walls"), the walls at zmin and zmax: the same product
    # and drift as System(confinement="slit", box=(Lx, Ly)), the dense matrix's to the
    # default tolerance 1e-10 of the largest entry
    x = np.array([[0.0, 0.0, 2.0], [3.0, 1.0, 3.5]])
    s = stokesian.NBody("periodic", "periodic", "two_walls")
    s.setParameters(Lx=8.0, Ly=9.0, zmin=0.5, zmax=5.5)
    s.initialize(viscosity=1.0, hydrodynamicRadius=1.0)
    s.setPositions(x)
    f = np.array([[1.0, 0.5, -0.3], [0.2, -1.0, 0.7]])
    u, _ = s.Mdot(f)
    slit = stokesian.System(x, 1.0, confinement="slit", boundary_height=0.5, gap=5.0,
                            box=(8.0, 9.0))
    assert np.array_equal(u.ravel(), slit.apply("F", f.ravel()))
    want = slit.mobility("F") @ f.ravel()
    assert np.abs(u.ravel() - want).max() <= 1e-10 * np.abs(want).max()
    lin, _ = s.divM()
    assert np.array_equal(lin.ravel(), slit.divergence("F"))
    with pytest.raises(RuntimeError, match="zmin and zmax"):
        stokesian.NBody("periodic", "periodic", "two_walls").setParameters(
            Lx=8.0, Ly=9.0, zmin=0.5)
    with pytest.raises(RuntimeError, match="zmin < zmax"):
        stokesian.NBody("periodic", "periodic", "two_walls").setParameters(
            Lx=8.0, Ly=9.0, zmin=0.5, zmax=0.5)
    with pytest.raises(ValueError, match="risen above the upper wall"):
        s.setPositions(np.array([[0.0, 0.0, 2.0], [3.0, 1.0, 6.0]]))


def test_periodic_along_a_wall_as_libmobilitys_dpstokes():
    # ("periodic", "periodic", "single_wall") with DPStokes' names: the same mobility as
    # System(confinement="wall", box=(Lx, Ly)): Mdot is the fast product (linked cells,
    # spectral Ewald), the dense matrix the direct sums, both to the default tolerance
    # 1e-10 of the result's largest entry; divM is System.divergence, the generated drift
    # (the same sums: 1e-15 of the largest), along the normal
    x = np.array([[0.0, 0.0, 2.0], [3.0, 1.0, 3.5]])
    s = stokesian.NBody("periodic", "periodic", "single_wall")
    s.setParameters(Lx=8.0, Ly=9.0, zmin=0.5, zmax=20.0, allowChangingBoxSize=False,
                    delta=1e-3, allowUnsafeForces=False)
    s.initialize(viscosity=1.0, hydrodynamicRadius=1.0)
    s.setPositions(x)
    f = np.array([[1.0, 0.5, -0.3], [0.2, -1.0, 0.7]])
    u, _ = s.Mdot(f)
    m = stokesian.System(x, 1.0, confinement="wall", params={"height": 0.5},
                         box=(8.0, 9.0)).mobility("F")
    # moment-major: the forces of every particle, x y z each
    want = m @ f.ravel()
    assert np.abs(u.ravel() - want).max() < 1e-10 * np.abs(want).max()
    lin, _ = s.divM()
    d = stokesian.System(x, 1.0, confinement="wall", params={"height": 0.5},
                         box=(8.0, 9.0)).divergence("F")
    assert np.abs(lin.ravel() - d).max() <= 1e-15 * np.abs(d).max()
    assert np.abs(d[2::3]).min() > 1e-3 and np.abs(d).max() == np.abs(d[2::3]).max()
    with pytest.raises(RuntimeError, match="Lx and Ly"):
        stokesian.NBody("periodic", "periodic", "single_wall").setParameters(Lx=8.0, zmin=0.0)
    with pytest.raises(RuntimeError, match="give one"):
        stokesian.NBody("periodic", "periodic", "single_wall").setParameters(
            Lx=8.0, Ly=9.0, zmin=0.0, wallHeight=1.0)
    with pytest.raises(RuntimeError, match="zmin applies only"):
        stokesian.NBody("open", "open", "single_wall").setParameters(zmin=0.0)


@pytest.mark.parametrize("wall", [True, False])
def test_fmm_tolerance_takes_the_fast_product(wall):
    # 1500 spheres in a slab above the wall: Mdot by the fast product within its
    # tolerance of the direct one (relative 2-norm, the fast product's own measure), and
    # identical to the library's fast product; in a periodic box the box's own at the
    # tolerance; refused out of range
    rng = np.random.default_rng(5)
    side = 60.0
    positions = np.column_stack([rng.uniform(0, side, 1500), rng.uniform(0, side, 1500),
                                 rng.uniform(1.5, 12.0, 1500)])
    forces = rng.normal(size=(1500, 3))
    for eps in (1e-3, 1e-6):
        fast = stokesian.NBody("open", "open", "single_wall" if wall else "open")
        exact = stokesian.NBody("open", "open", "single_wall" if wall else "open")
        if wall:
            fast.setParameters(wallHeight=0.0, fmm_tolerance=eps)
            exact.setParameters(wallHeight=0.0)
        else:
            fast.setParameters(fmm_tolerance=eps)
        for s in (fast, exact):
            s.initialize(viscosity=1.0, hydrodynamicRadius=0.5)
            s.setPositions(positions)
        u, _ = fast.Mdot(forces)
        v, _ = exact.Mdot(forces)
        assert np.linalg.norm(u - v) <= eps * np.linalg.norm(v)
        system = stokesian.System(positions, 0.5, confinement="wall" if wall else "free",
                                  overlap="rpy")
        assert np.array_equal(u.ravel(), system.apply("F", forces.ravel(), fmm=eps))
    # in a periodic box: the box's own fast product, its lattice sums to the tolerance
    grid = np.stack(np.meshgrid(*[np.arange(4.0)] * 3, indexing="ij"), -1).reshape(-1, 3)
    box = 10.0 * grid + rng.uniform(-2.0, 2.0, grid.shape)
    box_forces = rng.normal(size=grid.shape)
    periodic = stokesian.NBody("periodic", "periodic", "periodic")
    periodic.setParameters(Lx=40.0, Ly=40.0, Lz=40.0, fmm_tolerance=1e-3)
    exact = stokesian.NBody("periodic", "periodic", "periodic")
    exact.setParameters(Lx=40.0, Ly=40.0, Lz=40.0)
    for s in (periodic, exact):
        s.initialize(viscosity=1.0, hydrodynamicRadius=0.5)
        s.setPositions(box)
    u, _ = periodic.Mdot(box_forces)
    v, _ = exact.Mdot(box_forces)
    assert not np.array_equal(u, v)
    assert np.linalg.norm(u - v) <= 1e-3 * np.linalg.norm(v)
    with pytest.raises(stokesian.InputError, match="tolerance"):
        stokesian.NBody("open", "open", "open").setParameters(fmm_tolerance=1e-2)

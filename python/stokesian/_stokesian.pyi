"""Type stubs of the compiled module ``stokesian._stokesian`` (re-exported by ``stokesian``).

Units: any consistent set; SI is the usual choice (positions and radii in m, viscosity in
Pa s, forces in N, torques in N m, time in s, kT in J). Velocities come out in m/s,
rotation rates in rad/s, mobilities in the matching units (U/F in m/(N s)).

Sign: forces, torques and stresslets are those the particles exert ON THE FLUID, which
with no particle inertia equal the external force and torque acting on each particle
(gravity minus buoyancy, traps, magnetic torques): a sphere that sinks under gravity has
``fz = -(buoyant weight) < 0`` and moves along ``-z``. This is libMobility's convention
too (``M F`` with ``F`` the force on the particle).

Layout (docs/conventions.md, Swan & Brady Eq. 1): vectors and matrices are moment-major, particle-
major within a moment: all U (3N: U1x, U1y, U1z, U2x, ...), then all Omega (3N), then
all E (5N, in the orthonormal strain basis B1..B5 of the command line's help); the
mobility maps (F, L, S) to (U - U_inf, Omega - Omega_inf, -E_inf).

Errors: every error of the library (bad shapes, NaN, overlapping spheres, a sphere below
the wall, a matrix that is not positive definite, ...) raises :class:`InputError` with the
library's message; it is both a ``ValueError`` and a ``RuntimeError`` (libMobility's).

Arrays: NumPy arrays, anything ``numpy.asarray`` reads, or any CPU array offering
``__dlpack__`` (torch, jax, cupy, ...), read without a copy where possible.
"""

from typing import ClassVar, Dict, List, Literal, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike
Moments = Literal["F", "FT", "FTS"]
Confinement = Literal["free", "wall", "free_surface", "interface", "slit", "side_wall"]


class Param(TypedDict):
    """A declared parameter of a confinement."""

    name: str
    doc: str
    dimension: Literal["position", "length", "number"]
    default: Optional[float]
    example: float


class Declaration(TypedDict):
    """A confinement and its declared parameters."""

    name: Confinement
    title: str
    params: List[Param]


def confinements() -> List[Declaration]:
    """Every confinement, with one line on what it is and its declared parameters in
    order: name, one line of doc, dimension (``"position"`` of a plane along its normal,
    ``"length"``, or ``"number"`` such as a viscosity ratio), default (None: the
    parameter must be given) and a typical value. ``System(..., confinement=name,
    params={...})`` takes them by name."""

class InputError(RuntimeError, ValueError):
    """An input the solver refuses, or an error of the library, with the library's
    message. Both a ``RuntimeError`` (what libMobility raises, so that its scripts and
    tests catch it) and a ``ValueError`` (what ``System``'s users catch)."""

class System:
    """Spheres in Stokes flow in one confinement, validated once on construction.

    ``System(positions, radii, *, confinement="wall", params=None, viscosity=1.0,
    boundary_height=None, lam=None, gap=None, allow_overlap=False, overlap=None,
    box=None, periodic_tolerance=None)``

    positions: centres, shape (N, 3) or (3N,), length units.
    radii: one radius for all spheres, or one per sphere (shape (N,)).
    confinement: a name of :func:`confinements` (``-`` read as ``_``): ``"free"``
        (unbounded), ``"wall"`` (no-slip plane ``z = height``, fluid above),
        ``"free_surface"``, ``"interface"`` (needs ``lambda``, the viscosity ratio of the
        liquid below to the liquid holding the spheres, >= 0), ``"slit"`` (walls at
        ``z = height`` and ``height + gap``; needs ``gap`` > 0) or ``"side_wall"``
        (no-slip plane ``x = side``, fluid at ``x > side``).
    params: the confinement's declared parameters by name, e.g. ``{"side": 0.5}``; the
        others take their defaults (:func:`confinements`). An unknown, missing or
        non-finite parameter is a ValueError.
    boundary_height, lam, gap: other names of the parameters ``height``, ``lambda`` and
        ``gap`` (giving one both ways is a ValueError).
    viscosity: of the fluid holding the spheres (> 0).
    overlap: spheres overlapping each other or cutting a boundary: ``"refuse"`` (the
        default: a ValueError naming the particles), ``"rpy"`` (the Rotne-Prager-Yamakawa
        overlap forms, spheres cutting a boundary damped: symmetric positive definite; F
        and FT only, FTS and lubrication raise) or ``"far"`` (the far forms anyway).
    allow_overlap: ``True`` is ``overlap="far"`` (give one of the two).
    box: ``(Lx, Ly, Lz)``: a triply periodic box of unbounded fluid (``confinement=
        "free"``), the mobility summed over every periodic image by Ewald summation
        (F, FT and FTS, each with its fast product; Brownian dynamics too: the drift
        is zero, positions unwrapped; the lubricated resistance at FT and FTS; a trap
        raises).
        ``(Lx, Ly)``: periodic along a wall (``confinement="wall"``), unbounded above it
        (F, FT and FTS, the fast product at F and FT, the direct sums at FTS; Brownian
        dynamics with the generated drift, each sphere's height derivative of its
        periodic self mobility); with ``confinement="slit"``, periodic along both walls
        with the slit's exact Green's function (the same; Brownian dynamics with its
        drift).
        A sphere overlapping its own image or another's, or cutting a wall, raises.
    periodic_tolerance: relative truncation error of the periodic sums (default 1e-10).
    """

    def __init__(
        self,
        positions: ArrayLike,
        radii: Union[float, ArrayLike],
        *,
        confinement: Confinement = "wall",
        params: Optional[Dict[str, float]] = None,
        viscosity: float = 1.0,
        boundary_height: Optional[float] = None,
        lam: Optional[float] = None,
        gap: Optional[float] = None,
        allow_overlap: bool = False,
        overlap: Optional[Literal["refuse", "far", "rpy"]] = None,
        box: Optional[Sequence[float]] = None,
        periodic_tolerance: Optional[float] = None,
    ) -> None: ...
    def __len__(self) -> int: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]:
        """The centres, shape (N, 3)."""
    @property
    def radii(self) -> npt.NDArray[np.float64]:
        """The radii, shape (N,)."""
    @property
    def confinement(self) -> str:
        """The confinement's name."""
    @property
    def params(self) -> Dict[str, float]:
        """The confinement's parameters by name, defaults filled in."""
    @property
    def viscosity(self) -> float:
        """The viscosity."""
    def mobility(self, moments: Moments = "F") -> npt.NDArray[np.float64]:
        """The dense grand mobility, shape (kN, kN), k = 3 (F), 6 (FT), 11 (FTS), in the
        moment-major layout (module docstring); symmetric positive definite. U/F in
        length/(force time). Returned in Fortran order (the library's own), no copy."""
    def apply(
        self,
        moments: Moments,
        x: ArrayLike,
        *,
        precision: Literal["double", "single"] = "double",
        fmm: Optional[float] = None,
    ) -> npt.NDArray[np.float64]:
        """``M x`` without forming M: x has kN entries, moment-major (forces, then
        torques, then stresslets); the result likewise (U, Omega, -E_inf). Bit for bit
        independent of the number of threads. ``precision="single"`` runs the f32
        lanes (twice the pairs per instruction, about 1e-7 relative to the result's
        norm, any units of input) for F and FT; FTS runs in double precision.
        ``fmm=EPS`` (F and FT, EPS in [1e-10, 1e-3]): the fast multipole method to the
        relative tolerance EPS on the result's 2-norm, in double precision; ValueError
        at FTS, in a periodic box, or for EPS outside the range."""
    def velocities(
        self,
        forces: ArrayLike,
        torques: Optional[ArrayLike] = None,
        strain: Optional[ArrayLike] = None,
        lubrication: bool = False,
        pair_tolerance: Optional[float] = None,
        fmm: Optional[float] = None,
    ) -> Tuple[npt.NDArray[np.float64], Optional[npt.NDArray[np.float64]]]:
        """Velocities (N, 3) and rotation rates (N, 3) of the spheres under ``forces``
        and ``torques`` (on the fluid = on the particles; shape (N, 3) or (3N,)) in a
        fluid at rest or under the uniform rate of strain ``strain`` (shape (5,) in the
        orthonormal basis, or a symmetric traceless (3, 3) tensor, 1/time).

        The truncation follows the arguments: F (forces only; rotation rates None),
        FT (torques given, or ``lubrication``), FTS (``strain`` given: stresslets solved
        for, velocities relative to the ambient flow at each centre). ``lubrication``:
        the resistance of Eq. 19 (exact sphere-wall and two-sphere functions) solved by
        Cholesky; ValueError above a condition estimate of 1e14. ``pair_tolerance``
        (with ``lubrication``; default 1e-6): as in ``resistance``. ``fmm=EPS`` (F and
        FT without lubrication): the product by the fast multipole method, as in
        ``apply``."""
    def resistance(
        self,
        moments: Moments = "FT",
        lubrication: bool = True,
        pair_tolerance: Optional[float] = None,
    ) -> npt.NDArray[np.float64]:
        """The grand resistance (kN, kN), FT or FTS, same layout as the mobility; rows
        are what the particles exert on the fluid, columns (U - U_inf, Omega - Omega_inf,
        -E_inf). With ``lubrication`` Eq. 19, otherwise the inverse of the far-field
        mobility. ``pair_tolerance`` (default 1e-6, as ``--pair-tolerance``): each pair's
        exact two-sphere correction is kept where it may exceed this fraction of the
        smaller sphere's drag, and switched off smoothly beyond (0: every pair; inf:
        none; 1e-3 is cheaper in a dense suspension); ValueError if negative or NaN, or
        given without ``lubrication``."""
    def divergence(self, moments: Moments = "F") -> npt.NDArray[np.float64]:
        """``div M`` (3N at F; 6N at FT, the translational then the rotational rows),
        ``sum_b sum_j d/dx_bj M^ab_ij``, exact, from the generated divergence kernels;
        units of the mobility over length."""
    def brownian(
        self,
        steps: int,
        dt: float,
        kt: float = 1.0,
        seed: int = 0,
        *,
        moments: Literal["F", "FT"] = "F",
        weight: float = 0.0,
        repulsion_strength: float = 0.0,
        debye_length: float = 1.0,
        torque: Optional[Sequence[float]] = None,
        trap: float = 0.0,
        scheme: Literal["euler-maruyama", "fixman"] = "euler-maruyama",
        lanczos: Optional[float] = None,
        fmm: Optional[float] = None,
        drift: bool = True,
        lubrication: bool = False,
        rfd_step: float = 1e-3,
        pair_tolerance: Optional[float] = None,
        every: int = 1,
        max_rejections: int = 1000,
        hydrodynamics: bool = True,
    ) -> npt.NDArray[np.float64]:
        """Overdamped Brownian dynamics from this configuration, as ``stokesian brownian``
        (same options, same random numbers: ChaCha8 seeded with ``seed``, so the same
        seed gives the command line's trajectory bit for bit).

        ``x(t + dt) = x + (M F + kt div M) dt + sqrt(2 kt dt) M^(1/2) W``.

        steps: number of time steps; dt: the time step (> 0, time units); kt: thermal
        energy (> 0, energy units); weight: buoyant weight of each sphere, a force
        ``-weight e_z``; repulsion_strength, debye_length: a force
        ``strength exp(-gap / debye_length)`` from each boundary plane into the fluid;
        torque: FT only, the torque on every sphere; trap: stiffness of a harmonic trap
        towards the axis x = y = 0; scheme: Euler-Maruyama with the exact drift, or
        Fixman's midpoint; lanczos: tolerance of a Lanczos square root instead of
        Cholesky; drift: False leaves the drift out (wrong near a boundary; for
        comparison); lubrication: Brownian Stokesian dynamics with the resistance of
        Eq. 19 (drift by a random finite difference of step ``rfd_step`` radii;
        ``pair_tolerance`` as in ``resistance``);
        every: keep every K-th step (step 0 always); max_rejections: invalid steps (a
        sphere through a boundary or another) are redrawn, at most this many;
        hydrodynamics: False gives each sphere its isolated Stokes mobility; fmm=EPS
        (with lanczos): the Lanczos noise's products and M F by the fast multipole
        method to EPS (keep lanczos above EPS), and the drift each sphere's own
        terms, O(N) (its pair terms cancel: the direct sum's to round-off).

        Returns the frames: shape (frames, N, 3) at F, (frames, N, 7) at FT (centre,
        then the orientation quaternion w, x, y, z)."""

Output = Tuple[npt.NDArray[np.float64], Optional[npt.NDArray[np.float64]]]

class NBody:
    """libMobility's ``NBody`` solver with this library's kernels, so that a libMobility
    script runs by changing its import.

    Free space (``"open", "open", "open"``): the Rotne-Prager-Yamakawa mobility of
    spheres (overlapping ones with its overlap forms). Above a no-slip wall (``"open", "open", "single_wall"``,
    the wall at ``z = wallHeight``): the Rotne-Prager-Blake mobility of Swan & Brady
    (2007) and, beyond libMobility, its exact divergence. A triply periodic box
    (``"periodic", "periodic", "periodic"``, as libMobility's PSE solver; box lengths
    ``Lx, Ly, Lz`` through ``setParameters``): the RPY mobility summed over every periodic
    image by Ewald summation, zero drift, overlapping spheres refused. Periodic along a
    wall (``"periodic", "periodic", "single_wall"``, as libMobility's DPStokes; ``Lx, Ly``
    and the wall's height ``zmin`` through ``setParameters``): Blake's image system summed
    over the lateral images by Ewald summation, ``divM`` its generated drift (each
    sphere's height derivative of its periodic self mobility). Periodic between two walls
    (``"periodic", "periodic", "two_walls"``, as libMobility's DPStokes; the walls at
    ``zmin`` and ``zmax``): the slit's exact Green's function, ``Mdot`` the fast product,
    ``divM`` its drift. Two walls without periodic ``x, y`` and an open ``z`` with
    periodic ``x, y`` raise InputError. Overlapping spheres take the RPY overlap forms and spheres
    cutting the wall are damped, as in libMobility (``divM`` is then the exact divergence
    of the damped mobility); a
    centre below the wall raises InputError saying it has "fallen below the wall", in
    libMobility's words.

    Arrays: positions, forces and torques of any kind offering DLPack on the CPU (NumPy,
    torch, jax, cupy, ...); the results come back in the kind of the forces (else the
    torques, else the positions), as libMobility's do, always float64.

    Units and sign as libMobility: ``Mdot`` maps the force (torque) acting on each
    particle to its velocity (angular velocity), in the units of the viscosity, radius
    and positions given; the self mobility is ``1/(6 pi viscosity radius)``.
    Double precision only (``precision == "double"``).
    """

    precision: ClassVar[str]
    def __init__(self, periodicityX: str, periodicityY: str, periodicityZ: str) -> None: ...
    def setParameters(
        self,
        algorithm: str = "advise",
        Nbatch: int = -1,
        NperBatch: int = -1,
        wallHeight: Optional[float] = None,
        delta: float = 1e-3,
        *,
        Lx: Optional[float] = None,
        Ly: Optional[float] = None,
        Lz: Optional[float] = None,
        psi: Optional[float] = None,
        shearStrain: Optional[float] = None,
        zmin: Optional[float] = None,
        zmax: Optional[float] = None,
        allowChangingBoxSize: bool = False,
        allowUnsafeForces: bool = False,
        fmm_tolerance: Optional[float] = None,
    ) -> None:
        """``wallHeight``: the height of the wall; required with ``"single_wall"`` (also
        when ``setParameters`` is not called: ``setPositions`` then raises) and refused
        in free space. ``Nbatch``, ``NperBatch``: the particles are ``Nbatch``
        consecutive groups of ``NperBatch`` that do not interact (a block-diagonal
        mobility); -1: one batch, or all particles in each; ``setPositions`` raises
        InputError unless ``Nbatch * NperBatch`` is the number of particles.
        ``algorithm`` (checked) and ``delta`` (libMobility's random finite difference
        step) are accepted and change nothing: every algorithm computes the same here,
        and ``divM`` is exact. ``Lx, Ly, Lz``: the box of a triply periodic solver
        (required there, refused otherwise); ``psi`` (PSE's splitting parameter) is
        accepted and changes nothing (the split is chosen for the tolerance);
        ``shearStrain`` other than 0 raises. Periodic along a wall (DPStokes' names):
        ``Lx, Ly`` (required, ``Lz`` refused) and ``zmin``, the wall's height (or
        ``wallHeight``; both must agree); ``zmax``, ``allowChangingBoxSize`` and
        ``allowUnsafeForces`` are accepted and change nothing (no grid here).
        ``fmm_tolerance`` (beyond libMobility): ``Mdot`` and the Lanczos products of
        ``sqrtMdotW`` by the fast multipole method to this relative 2-norm tolerance in
        ``[1e-10, 1e-3]`` (``System.apply(..., fmm=)``; in a periodic box, the box's own
        fast product with its lattice sums to it); ``divM`` each sphere's own terms,
        ``O(N)`` (the pair terms cancel: equal to the direct sum to round-off)."""
    def initialize(
        self,
        viscosity: float,
        hydrodynamicRadius: Union[float, ArrayLike],
        includeAngular: bool = False,
        tolerance: float = 1e-4,
        seed: Optional[int] = None,
    ) -> None:
        """``hydrodynamicRadius``: one radius, or (beyond libMobility) an array of N
        radii. ``includeAngular``: torques in, angular velocities out. ``tolerance``:
        relative tolerance of the Lanczos square root in ``sqrtMdotW``. ``seed``: of
        the noise (None: drawn from the operating system)."""
    def setPositions(self, positions: ArrayLike) -> None:
        """Positions of shape (N, 3) or (3N,); the outputs of ``sqrtMdotW`` and ``divM``
        take this shape and kind of array. Invalid positions (NaN, two equal centres, a
        centre below the wall, batches that do not divide N) raise InputError
        and leave the previous positions in place."""
    def Mdot(self, forces: Optional[ArrayLike] = None, torques: Optional[ArrayLike] = None) -> Output:
        """``(linear, angular) = M [F; T]``: velocities (length/time) and angular
        velocities (rad/time) from forces and torques on the particles. ``linear`` is
        shaped like the forces (else the torques), ``angular`` like the torques (else
        the forces), each (N, 3) or (3N,); ``angular`` is None unless
        ``includeAngular``. Torques without ``includeAngular``, or calling before
        ``setPositions``, raise InputError."""
    def sqrtMdotW(self, prefactor: float = 1.0) -> Output:
        """``prefactor M^(1/2) W``, W standard normal (covariance ``prefactor^2 M``),
        by a Lanczos iteration to ``tolerance``."""
    def divM(self, prefactor: float = 1.0) -> Output:
        """``prefactor div M`` (``sum_j d M_ij / d x_j``), exact and deterministic, from
        the generated divergence kernels (libMobility's is a random finite difference
        that differs from call to call); exactly zero in free space."""
    def LangevinVelocities(
        self,
        dt: float,
        kbt: float,
        forces: Optional[ArrayLike] = None,
        torques: Optional[ArrayLike] = None,
    ) -> Output:
        """``M [F; T] + sqrt(2 kbt / dt) M^(1/2) W + kbt div M``: the velocities of one
        Euler-Maruyama step of length ``dt`` at thermal energy ``kbt``. Each output is
        shaped like its own input, else like the positions."""
    def clean(self) -> None:
        """Forget the parameters and positions (``initialize`` again before use)."""

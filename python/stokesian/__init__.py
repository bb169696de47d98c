"""stokesian: hydrodynamic interactions of spheres in Stokes flow, unbounded and near a
plane wall, a free surface, a liquid-liquid interface, in a slit or beside a side wall
(Swan & Brady, Phys. Fluids 19, 113306, 2007), from generated kernels.

- :class:`System`: the whole solver (dense grand mobility F, FT, FTS; matrix-free
  products; velocities with or without lubrication; the resistance of Eq. 19; the
  Brownian drift; Brownian dynamics).
- :func:`confinements`: every confinement and its declared parameters, which
  ``System(..., confinement=NAME, params={...})`` takes by name.
- :class:`NBody`: libMobility's interface (``NBody("open", "open", "open")`` or
  ``("open", "open", "single_wall")``), so that a libMobility script changes one import.

Units: any consistent set (SI: m, Pa s, N, N m, s). Sign: forces and torques are those
the particles exert on the fluid, i.e. the external force and torque on each particle;
velocities are along the force (the mobility is positive definite). Every error of the
library and every refused input raises :class:`InputError` with the library's message: a
subclass of both ``ValueError`` and ``RuntimeError`` (libMobility's exception), so either
``except`` catches it.
"""

from ._stokesian import InputError, NBody, System, confinements

__all__ = ["InputError", "NBody", "System", "confinements"]

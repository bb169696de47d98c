"""Spheres sedimenting towards a wall under gravity, with Brownian motion.

Run twice: once with ``stokesian.System.brownian`` (the whole integrator, in Rust), and
once step by step through ``stokesian.NBody``, as a libMobility script would
(``LangevinVelocities`` gives ``M F + sqrt(2 kT/dt) M^(1/2) W + kT div M``; the drift
``kT div M`` is what keeps the spheres from piling into the wall in a wrong way).
Units: radius 1, viscosity 1, kT 1; the buoyant weight 4 kT/a (gravitational height
a/4), a screened repulsion from the wall keeps the spheres off it. Both runs draw the same
standard normal numbers (the same seed), so their curves differ only by the square root
of M they apply them to (Cholesky factor and Lanczos M^(1/2)) and stay close.

    python sedimentation.py [--steps 5000] [--no-plot]

Plots the mean height against time with matplotlib if it is installed (sedimentation.png).
"""

import argparse

import numpy as np

import stokesian

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--steps", type=int, default=5000)
parser.add_argument("--no-plot", action="store_true")
args = parser.parse_args()

n, dt, kt, weight = 16, 5e-3, 1.0, 4.0
strength, debye = 20.0, 0.1  # wall repulsion: strength exp(-gap / debye)
rng = np.random.default_rng(0)
xy = np.array([(i % 4, i // 4) for i in range(n)], dtype=float) * 3.5
start = np.column_stack([xy + rng.uniform(-0.3, 0.3, (n, 2)), rng.uniform(3.0, 6.0, n)])

# 1. the integrator of the library: (frames, N, 3)
system = stokesian.System(start, 1.0, confinement="wall")
traj = system.brownian(args.steps, dt, kt, seed=1, weight=weight,
                       repulsion_strength=strength, debye_length=debye, every=10)
heights = traj[:, :, 2].mean(axis=1)

# 2. the same physics through libMobility's interface
solver = stokesian.NBody("open", "open", "single_wall")
solver.setParameters(wallHeight=0.0)
solver.initialize(viscosity=1.0, hydrodynamicRadius=1.0, seed=1)
x = start.copy()
solver.setPositions(x)
nbody_heights = [x[:, 2].mean()]
for step in range(1, args.steps + 1):
    forces = np.zeros_like(x)
    forces[:, 2] = -weight + strength * np.exp(-(x[:, 2] - 1.0) / debye)
    while True:
        v, _ = solver.LangevinVelocities(dt=dt, kbt=kt, forces=forces)
        try:  # a step that makes spheres overlap is refused: redraw it
            solver.setPositions(x + v * dt)
        except ValueError:
            continue
        x = x + v * dt
        break
    if step % 10 == 0:
        nbody_heights.append(x[:, 2].mean())

t = np.arange(len(heights)) * 10 * dt
print(f"mean height: {heights[0]:.3f} at t = 0, {heights[-1]:.3f} (System.brownian) and "
      f"{nbody_heights[-1]:.3f} (NBody) at t = {t[-1]:.2f}")

if not args.no_plot:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot")
    else:
        plt.plot(t, heights, label="System.brownian")
        plt.plot(t, nbody_heights, label="NBody.LangevinVelocities")
        plt.xlabel("time [a^2 eta / kT]")
        plt.ylabel("mean height [a]")
        plt.legend()
        plt.savefig("sedimentation.png", dpi=120)
        print("wrote sedimentation.png")

"""Shared fixtures: the command-line binary the tests compare with, and scratch files."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli():
    """Run ``stokesian`` (``$STOKESIAN_CLI``, default target/release/stokesian, built by
    ``cargo test --workspace --release`` or ``cargo build --release -p stokesian-cli``).
    Missing is a failure, not a skip: these tests are the comparison with the CLI."""
    path = Path(os.environ.get("STOKESIAN_CLI", ROOT / "target" / "release" / "stokesian"))
    assert path.exists(), f"{path} not found: build it with cargo build --release -p stokesian-cli"

    def run(*args, ok=True):
        p = subprocess.run([str(path), *map(str, args)], capture_output=True, text=True)
        if ok:
            assert p.returncode == 0, p.stderr
        return p

    return run


def write_particles(path, positions, radii):
    """particles.csv for the CLI, every number in shortest round-trip form (repr)."""
    positions = np.asarray(positions, dtype=float).reshape(-1, 3)
    radii = np.broadcast_to(np.asarray(radii, dtype=float), (len(positions),))
    lines = ["x,y,z,radius"]
    lines += [",".join(repr(float(v)) for v in (*x, a)) for x, a in zip(positions, radii)]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_forces(path, forces, torques=None):
    """forces.csv: fx,fy,fz (and tx,ty,tz)."""
    forces = np.asarray(forces, dtype=float).reshape(-1, 3)
    header = "fx,fy,fz"
    rows = forces
    if torques is not None:
        header += ",tx,ty,tz"
        rows = np.hstack([forces, np.asarray(torques, dtype=float).reshape(-1, 3)])
    lines = [header] + [",".join(repr(float(v)) for v in r) for r in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def read_csv(path):
    """A CSV of numbers written by the CLI (shortest round-trip form: exact)."""
    return np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def wall_configuration(n=5, seed=1):
    """n unit spheres above the wall z = 0, well apart, heights 1.5 to 4 radii; random
    forces and torques."""
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(n)))
    grid = np.array([(i % side, i // side) for i in range(n)], dtype=float) * 3.1
    xy = grid + rng.uniform(-0.4, 0.4, size=(n, 2))
    z = rng.uniform(1.5, 4.0, size=n)
    positions = np.column_stack([xy, z])
    forces = rng.normal(size=(n, 3))
    torques = rng.normal(size=(n, 3))
    return positions, forces, torques

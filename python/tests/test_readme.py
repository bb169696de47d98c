"""README's examples are code that runs: the Python block is executed here, and the Rust
block is the one `stokesian/examples/quickstart.rs` compiles (cargo builds examples in
`cargo test`)."""

import re

import numpy as np

from conftest import ROOT


def blocks(lang):
    text = (ROOT / "README.md").read_text()
    return re.findall(rf"```{lang}\n(.*?)```", text, re.S)


def test_the_python_example_runs():
    (block,) = blocks("python")
    scope = {}
    exec(compile(block, "README.md", "exec"), scope)
    # what its comments promise: an SPD (6N, 6N) FT mobility, both spheres' velocities
    # under gravity pointing down, a trajectory of (frames, N, 3)
    m = scope["m"]
    assert m.shape == (18, 18)
    np.testing.assert_allclose(m, m.T, rtol=0, atol=1e-15 * abs(m).max())
    assert np.linalg.eigvalsh(m).min() > 0
    assert (scope["u"][:, 2] < 0).all()
    assert scope["traj"].shape == (101, 3, 3)


def test_the_rust_example_is_the_quickstart():
    (block,) = blocks("rust")
    quickstart = (ROOT / "stokesian" / "examples" / "quickstart.rs").read_text()
    start = quickstart.index("// README, from here to the blank line\n")
    section = quickstart[start:].split("\n", 1)[1].split("\n\n", 1)[0]
    body = [line for line in block.splitlines() if not line.startswith("use ")]
    assert [line.strip() for line in section.splitlines()] == [
        line.strip() for line in body if line.strip()
    ]

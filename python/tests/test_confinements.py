"""Confinements by their declarations: ``stokesian.confinements()`` lists them,
``System(..., confinement=NAME, params={...})`` builds any of them by its declared
parameters (the keywords ``boundary_height``, ``lam``, ``gap`` as other names of
``height``, ``lambda``, ``gap``), and wrong parameters are ValueErrors naming them. The
side wall ``x = s`` against the wall ``z = 0`` turned, as in the Rust tests
(tests/tests/integration/lubrication/side_wall.rs)."""

import math

import numpy as np
import pytest

import stokesian

# the rotation taking e3 to e1 (columns t1, t2, n = e2, e3, e1): a permutation, so that
# the turned positions are exact
R = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
SIDE = 0.25


def test_every_confinement_is_listed_with_its_parameters():
    listed = {c["name"]: c for c in stokesian.confinements()}
    assert set(listed) == {"free", "wall", "free_surface", "interface", "slit", "side_wall"}
    for c in listed.values():
        assert c["title"]
        for p in c["params"]:
            assert set(p) == {"name", "doc", "dimension", "default", "example"}
            assert p["dimension"] in ("position", "length", "number")
            assert math.isfinite(p["example"])
    params = lambda name: [(p["name"], p["default"]) for p in listed[name]["params"]]
    assert params("free") == []
    assert params("wall") == [("height", 0.0)]
    assert params("interface") == [("height", 0.0), ("lambda", None)]
    assert params("slit") == [("height", 0.0), ("gap", None)]
    assert params("side_wall") == [("side", 0.0)]
    # each builds from its examples, and reports them back
    x = np.array([[5.0, 0.5, 5.0]])
    for c in listed.values():
        given = {p["name"]: p["example"] for p in c["params"]}
        s = stokesian.System(x, 1.0, confinement=c["name"], params=given)
        assert s.confinement == c["name"] and s.params == given


def test_the_keywords_are_other_names_of_the_parameters():
    x = np.array([[0.0, 0.0, 2.0], [2.5, 0.3, 3.0]])
    pairs = [
        (dict(confinement="wall", boundary_height=0.25), dict(confinement="wall", params={"height": 0.25})),
        (dict(confinement="interface", lam=0.3), dict(confinement="interface", params={"lambda": 0.3})),
        (dict(confinement="slit", gap=40.0), dict(confinement="slit", params={"gap": 40.0})),
    ]
    for old, new in pairs:
        a, b = stokesian.System(x, 1.0, **old), stokesian.System(x, 1.0, **new)
        assert a.params == b.params
        assert np.array_equal(a.mobility("FTS"), b.mobility("FTS"))
    # defaults filled in
    assert stokesian.System(x, 1.0, confinement="slit", gap=40.0).params == {"height": 0.0, "gap": 40.0}
    assert stokesian.System(x, 1.0).params == {"height": 0.0}


def side_and_wall(positions, radius):
    """The side-wall system and the wall system of the same spheres turned to z = 0."""
    side = stokesian.System(positions, radius, confinement="side_wall", params={"side": SIDE})
    turned = (positions - [SIDE, 0.0, 0.0]) @ R  # R^T (x - s e1), row by row
    wall = stokesian.System(turned, radius, confinement="wall")
    return side, wall


def test_a_side_wall_from_params_is_the_wall_turned():
    # a sphere at gap 0.01 from the side wall, a second at gap 0.02 from it, a third
    # further out; at negative z (nothing is measured from z = 0)
    positions = np.array([[SIDE + 1.01, -0.4, -2.0], [SIDE + 1.01, 1.62, -2.0],
                          [SIDE + 3.0, 1.0, 1.5]])
    side, wall = side_and_wall(positions, 1.0)
    assert side.confinement == "side_wall" and side.params == {"side": SIDE}
    # FT, moment-major: R on each sphere's velocity and on its rotation
    q = np.kron(np.eye(6), R)
    # the kernels agree to 1e-12 of each block (physics::rotated_planes); the whole to
    # 1e-14 of its norm, and the lubricated resistance (the mobility's condition number
    # is below 1e2 here) to 1e-13
    m_side, m_wall = side.mobility("FT"), q @ wall.mobility("FT") @ q.T
    assert np.linalg.norm(m_side - m_wall) <= 1e-14 * np.linalg.norm(m_wall)
    r_side, r_wall = side.resistance("FT"), q @ wall.resistance("FT") @ q.T
    assert np.linalg.norm(r_side - r_wall) <= 1e-13 * np.linalg.norm(r_wall)
    # lubrication acts along the side wall's normal: the first sphere's resistance to
    # moving towards it (x) far above the far field's
    far = side.resistance("FT", lubrication=False)
    assert r_side[0, 0] > 10 * far[0, 0]


def test_wrong_parameters_are_value_errors():
    x = np.array([[2.0, 0.0, 2.0]])
    cases = [
        (dict(confinement="side_wall", params={"height": 1.0}),
         "`side_wall` has no parameter `height` \\(its parameters: side\\)"),
        (dict(confinement="side_wall", boundary_height=1.0),
         "boundary_height: `side_wall` has no parameter `height`"),
        (dict(confinement="free", params={"height": 0.0}), "`free` has no parameters"),
        (dict(confinement="interface", params={"height": 0.5}),
         "`interface` needs the parameter `lambda`"),
        (dict(confinement="wall", boundary_height=0.5, params={"height": 0.5}),
         "boundary_height and params\\['height'\\]|boundary_height and params\\[\"height\"\\]"),
        (dict(confinement="side_wall", params={"side": math.nan}),
         "the parameter `side` must be finite \\(got NaN\\)"),
        (dict(confinement="slit", gap=math.inf), "gap: the parameter `gap` must be finite"),
        (dict(confinement="side_wall", params={"side": "left"}), "must be a number"),
        (dict(confinement="side_wall", params={1: 0.0}), "names must be strings"),
        (dict(confinement="moon", params={}), "unknown confinement `moon`"),
        # the parameter's own check: a slit width must be positive
        (dict(confinement="slit", params={"gap": -1.0}), "gap = -1"),
    ]
    for kwargs, message in cases:
        with pytest.raises(ValueError, match=message):
            stokesian.System(x, 0.5, **kwargs)


def test_spheres_beyond_or_cutting_the_side_wall_are_refused():
    params = {"side": SIDE}
    with pytest.raises(ValueError, match="not inside the fluid: signed distance -0.5 from the "
                                         "boundary, no slip at x1 = 0.25"):
        stokesian.System([[SIDE - 0.5, 0.0, 3.0]], 0.2, confinement="side_wall", params=params)
    with pytest.raises(ValueError, match="overlaps the boundary, no slip at x1 = 0.25"):
        stokesian.System([[SIDE + 0.5, 0.0, -3.0]], 1.0, confinement="side_wall", params=params)
    # accepted where overlaps are allowed; never beyond the plane
    stokesian.System([[SIDE + 0.5, 0.0, -3.0]], 1.0, confinement="side_wall", params=params,
                     allow_overlap=True)

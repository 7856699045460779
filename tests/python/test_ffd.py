"""sculpt.FFD gives PyGeM's results with PyGeM's parameters. The reference is PyGeM's own algorithm
(pygem/ffd.py, FFD.__call__: the box fitted to the unit cube by least squares, Bernstein polynomials in power
form, the box's points moved and mapped back, the rest left), written again here in numpy and run on the
same parameters: for PyGeM's test_ffd_sphere_mod (its 3x2x2 box, rotated 10 degrees about y and 15 about z) and
on random boxes of every size."""
import math
import time

import numpy as np
import pytest

import sculpt


def rotation(rot_angle):
    """PyGeM's angles2matrix(rad(z), rad(y), rad(x)): Rx Ry Rz, each skipped when its angle is 0."""
    ax, ay, az = np.radians(rot_angle)
    matrices = []
    if az:
        matrices.append(np.array([[math.cos(az), -math.sin(az), 0], [math.sin(az), math.cos(az), 0], [0, 0, 1]]))
    if ay:
        matrices.append(np.array([[math.cos(ay), 0, math.sin(ay)], [0, 1, 0], [-math.sin(ay), 0, math.cos(ay)]]))
    if ax:
        matrices.append(np.array([[1, 0, 0], [0, math.cos(ax), -math.sin(ax)], [0, math.sin(ax), math.cos(ax)]]))
    result = np.eye(3)
    for m in matrices[::-1]:
        result = result.dot(m)
    return result


def affine_fit(start, end):
    """PyGeM's fit_affine_transformation: the least-squares affine map from start points to end points."""
    pad = lambda x: np.hstack([x, np.ones((x.shape[0], 1))])
    A = np.linalg.lstsq(pad(start), pad(end), rcond=None)[0]
    return lambda src: pad(np.atleast_2d(src)).dot(A)[:, :-1]


def pygem_ffd(points, n, origin, length, rot_angle, mu_x, mu_y, mu_z):
    """PyGeM's FFD.__call__, step by step."""
    reference = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    vertices = origin + np.vstack([np.zeros((1, 3)), rotation(rot_angle).dot(np.diag(length)).T])
    psi = affine_fit(vertices - origin, reference)
    inverse_psi = affine_fit(reference, vertices - origin)
    u = psi(points - origin)
    inside = np.all((u >= 0.0) & (u <= 1.0), axis=1)
    ui = u[inside]
    basis = []
    for axis in range(3):
        d = n[axis]
        basis.append(np.array([math.comb(d - 1, i) * np.power(1 - ui[:, axis], d - 1 - i) * np.power(ui[:, axis], i)
                               for i in range(d)]))
    shift = np.zeros((3, ui.shape[0]))
    for j in range(n[1]):
        for k in range(n[2]):
            yz = basis[1][j] * basis[2][k]
            for i in range(n[0]):
                b = basis[0][i] * yz
                shift[0] += b * mu_x[i, j, k]
                shift[1] += b * mu_y[i, j, k]
                shift[2] += b * mu_z[i, j, k]
    out = points.copy()
    out[inside] = inverse_psi(shift.T + ui) + origin
    return out, inside


def sphere_points(count, radius, rng):
    """Points on a sphere (PyGeM's meshpoints_sphere_orig is a sphere of 7200 points about the origin)."""
    v = rng.normal(size=(count, 3))
    return radius * v / np.linalg.norm(v, axis=1)[:, None]


def relative_error(a, b, scale):
    return np.max(np.abs(a - b)) / scale


def test_pygem_sphere_mod_case():
    rng = np.random.default_rng(7200)
    points = sphere_points(7200, 50.0, rng)
    ffd = sculpt.FFD([3, 2, 2])
    ffd.box_origin = np.array([-20.0, -55.0, -45.0])
    ffd.box_length = np.array([45.0, 90.0, 90.0])
    ffd.rot_angle = np.array([0.0, 10.0, 15.0])
    ffd.array_mu_x[2, 0, 0] = 0.8
    ffd.array_mu_y[2, 0, 0] = -0.5
    ffd.array_mu_z[2, 0, 0] = -1.0
    ours = ffd(points)
    reference, inside = pygem_ffd(points, [3, 2, 2], ffd.box_origin, ffd.box_length, ffd.rot_angle, ffd.array_mu_x,
                                  ffd.array_mu_y, ffd.array_mu_z)
    assert 1000 < inside.sum() < 7200
    assert relative_error(ours, reference, 90.0) < 1e-12
    assert np.array_equal(ours[~inside], points[~inside])  # outside: exactly where they were
    assert np.max(np.abs(ours[inside] - points[inside])) > 1.0  # and the inside really moved


def test_random_boxes_of_every_size_match_pygem():
    rng = np.random.default_rng(1986)
    cases = 0
    for trial in range(60):
        n = [int(x) for x in rng.integers(1, 7, size=3)]
        ffd = sculpt.FFD(n)
        assert ffd.array_mu_x.shape == tuple(n)
        ffd.box_origin = rng.uniform(-5, 5, size=3)
        ffd.box_length = rng.uniform(0.5, 8, size=3)
        ffd.rot_angle = rng.uniform(-180, 180, size=3) * (rng.random(3) < 0.7)
        for mu in (ffd.array_mu_x, ffd.array_mu_y, ffd.array_mu_z):
            mu[...] = rng.uniform(-0.4, 0.4, size=n)
        count = int(rng.integers(1, 3000))
        points = rng.uniform(-10, 10, size=(count, 3))
        ours = ffd(points)
        reference, _ = pygem_ffd(points, n, ffd.box_origin, ffd.box_length, ffd.rot_angle, ffd.array_mu_x, ffd.array_mu_y,
                                 ffd.array_mu_z)
        scale = max(1.0, float(np.max(np.abs(reference))))
        assert relative_error(ours, reference, scale) < 1e-12, (trial, n)
        cases += 1
    assert cases == 60


def test_parameters_behave_as_pygem_and_bad_ones_are_named():
    ffd = sculpt.FFD()
    assert list(ffd.n_control_points) == [2, 2, 2]
    ffd.array_mu_x[1, 1, 1] = 0.3
    ffd.n_control_points = [4, 3, 2]  # resets the displacements, as PyGeM does
    assert ffd.array_mu_x.shape == (4, 3, 2) and not ffd.array_mu_x.any()
    # The undeformed box is the identity, inside and out.
    points = np.random.default_rng(3).uniform(-1, 2, size=(500, 3))
    assert np.array_equal(sculpt.FFD([3, 3, 3])(points), points)
    with pytest.raises(sculpt.Error, match=r"n_control_points\[1\] is 0"):
        ffd.n_control_points = [2, 0, 2]
    ffd.array_mu_y = np.zeros((2, 2, 2))
    with pytest.raises(sculpt.Error, match=r"array_mu_y must have the shape of n_control_points \(4, 3, 2\)"):
        ffd(points)
    ffd.array_mu_y = np.zeros((4, 3, 2))
    ffd.box_length = [1.0, -1.0, 1.0]
    with pytest.raises(sculpt.Error, match=r"box_length must be finite and > 0"):
        ffd(points)
    ffd.box_length = [1.0, 1.0, 1.0]
    with pytest.raises(sculpt.Error, match=r"the points must be an n x 3 array"):
        ffd(points[:, :2])


def test_a_million_points_take_a_fraction_of_pygems_time(capsys):
    """Reported, not asserted against a clock: PyGeM takes 3.9 s for 1M points on this machine."""
    rng = np.random.default_rng(1)
    points = rng.uniform(-1, 1, size=(1_000_000, 3))
    ffd = sculpt.FFD([3, 2, 2])
    ffd.box_origin = np.array([-1.0, -1.0, -1.0])
    ffd.box_length = np.array([2.0, 2.0, 2.0])
    ffd.rot_angle = np.array([0.0, 10.0, 15.0])
    ffd.array_mu_x[2, 0, 0] = 0.3
    start = time.perf_counter()
    ours = ffd(points)
    seconds = time.perf_counter() - start
    start = time.perf_counter()
    reference, _ = pygem_ffd(points, [3, 2, 2], ffd.box_origin, ffd.box_length, ffd.rot_angle, ffd.array_mu_x, ffd.array_mu_y,
                             ffd.array_mu_z)
    reference_seconds = time.perf_counter() - start
    assert relative_error(ours, reference, 2.0) < 1e-12
    with capsys.disabled():
        print(f"\nFFD of 1M points: sculpt.FFD {seconds:.3f} s, PyGeM's algorithm in numpy {reference_seconds:.3f} s")


def test_plain_ffd_in_a_session_is_pygems_and_a_test_keeps_the_boundary_with_its_reason():
    """PyGeM's box as an oriented parallelepiped lattice tool in a Session: with the injectivity test off every
    control point moves and the vertices outside stay (PyGeM's result); with a test on the boundary of a
    lattice that holds only part of the mesh stays pinned, and the refusal says why and how to lift it."""
    from conftest import icosphere
    V, F = icosphere(3)
    V = 50.0 * V
    origin, length, angle = np.array([-20.0, -55.0, -45.0]), np.array([45.0, 90.0, 90.0]), np.array([0.0, 10.0, 15.0])
    R = rotation(angle)
    edges = (R.dot(np.diag(length))).T  # rows: the edge vectors e_u, e_v, e_w
    lattice = {"kind": "parallelepiped", "origin": list(origin), "edges": edges.tolist(), "chunks": [1, 1, 1], "degree": [2, 1, 1]}
    mu = np.array([0.8, -0.5, -1.0])
    ffd = sculpt.FFD([3, 2, 2])
    ffd.box_origin, ffd.box_length, ffd.rot_angle = origin, length, angle
    ffd.array_mu_x[2, 0, 0], ffd.array_mu_y[2, 0, 0], ffd.array_mu_z[2, 0, 0] = mu
    expected = ffd(V)
    moved = np.any(expected != V, axis=1)
    assert 20 < moved.sum() < len(V)

    plain = sculpt.Session(V, F, injectivity={"mode": "off"})
    assert plain.run({"op": "add_lattice", "name": "pygem", "lattice": lattice})["status"] == "applied"
    assert plain.run({"op": "freeze", "index": 0, "pin_layers": 0})["status"] == "applied"
    report = plain.move_control_points([[2, 0, 0]], by=R.dot(mu * length).tolist())
    assert report["status"] == "applied", report
    assert relative_error(plain.positions, expected, 90.0) < 1e-12
    assert np.array_equal(plain.positions[~moved], V[~moved])  # the vertices outside stay where they are

    tested = sculpt.Session(V, F, injectivity={"mode": "conic"})
    tested.run({"op": "add_lattice", "name": "pygem", "lattice": lattice})
    tested.run({"op": "freeze", "index": 0, "pin_layers": 0})
    with pytest.raises(sculpt.Error, match=r"control point \[2,0,0\] is pinned: the lattice holds only part of the mesh.*"
                                           r"set the injectivity test off for a plain FFD"):
        tested.move_control_points([[2, 0, 0]], by=R.dot(mu * length).tolist())
    assert np.array_equal(tested.positions, V)

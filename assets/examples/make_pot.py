#!/usr/bin/env python3
"""Writes pot.obj: the pot of assets/examples/pot.json (Song & Yang 2005, Fig. 12), a closed surface of revolution
about the z axis: a flat base, a bellied outer wall, a neck and a flared rim, a rounded lip, and an inner wall
`WALL` thinner down to an inner floor. Run from this folder: python3 make_pot.py  (deterministic output)."""
import math

SEGMENTS = 48   # around the axis
WALL_ROWS = 28  # profile points per wall
WALL = 0.04     # wall thickness
FLOOR = 0.06    # height of the inner floor


def outer_radius(z):
    """The outer wall: a belly at z ~ 0.4, a neck at z ~ 0.82, the rim flaring out to z = 1."""
    belly = 0.44 + 0.08 * math.sin(math.pi * min(z / 0.82, 1.0)) ** 1.5
    flare = 0.12 * max(0.0, (z - 0.82) / 0.18) ** 2
    neck = -0.10 * math.sin(math.pi * min(max((z - 0.45) / 0.55, 0.0), 1.0)) ** 2
    return belly + flare + neck


def profile():
    """(r, z) from the outer bottom centre round the lip to the inner floor's centre, the poles excluded."""
    points = []
    r0 = outer_radius(0.0)
    points += [(r0 * k / 4.0, 0.0) for k in range(1, 4)]                                  # the base
    points += [(outer_radius(z), z) for z in (i / (WALL_ROWS - 1) for i in range(WALL_ROWS))]  # outer wall, up
    top = outer_radius(1.0)
    for k in range(1, 6):                                                                 # the lip, over the top
        a = math.pi * k / 6.0
        points.append((top - WALL / 2 + WALL / 2 * math.cos(a), 1.0 + WALL / 2 * math.sin(a)))
    inner = [(outer_radius(z) - WALL, z) for z in (1.0 - (1.0 - FLOOR) * i / (WALL_ROWS - 1) for i in range(WALL_ROWS))]
    points += inner                                                                       # inner wall, down
    r1 = inner[-1][0]
    points += [(r1 * k / 4.0, FLOOR) for k in range(3, 0, -1)]                            # the inner floor
    return points


def main():
    rows = profile()
    vertices = [(0.0, 0.0, 0.0)]  # bottom pole
    for r, z in rows:
        for s in range(SEGMENTS):
            a = 2.0 * math.pi * s / SEGMENTS
            vertices.append((r * math.cos(a), r * math.sin(a), z))
    vertices.append((0.0, 0.0, FLOOR))  # inner floor's pole
    top_pole = len(vertices)  # 1-based id of the last vertex
    ring = lambda i, s: 2 + i * SEGMENTS + s % SEGMENTS  # 1-based id of profile row i, segment s
    faces = []
    for s in range(SEGMENTS):  # outward normals: the profile runs outside-up, then inside-down
        faces.append((1, ring(0, s + 1), ring(0, s)))
        for i in range(len(rows) - 1):
            faces.append((ring(i, s), ring(i, s + 1), ring(i + 1, s + 1)))
            faces.append((ring(i, s), ring(i + 1, s + 1), ring(i + 1, s)))
        last = len(rows) - 1
        faces.append((ring(last, s), ring(last, s + 1), top_pole))
    with open("pot.obj", "w") as out:
        out.write("# A pot: a closed surface of revolution about z, base at z = 0, rim at z = 1 (made by make_pot.py;\n")
        out.write("# DMFFD Sculpt examples: pot.json, Song & Yang 2005 Fig. 12)\n")
        for v in vertices:
            out.write("v %.6f %.6f %.6f\n" % v)
        for f in faces:
            out.write("f %d %d %d\n" % f)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes the light-stripe system's scene files (paper 004, section 5): OBJ,
mm, table frame (z up, table top z = 0, the scanned square x, y in
[-200, 200]). Faces are counter-clockwise seen from outside. Run from this
folder: ./make_scenes.py"""
import math


def box(x0, y0, z0, x1, y1, z1):
    v = [(x, y, z) for z in (z0, z1) for y in (y0, y1) for x in (x0, x1)]
    # indices: 0 (x0,y0,z0) 1 (x1,y0,z0) 2 (x0,y1,z0) 3 (x1,y1,z0), 4.. same at z1
    f = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return v, f


def write(name, comment, parts):
    with open(name, "w") as out:
        for line in comment.strip().splitlines():
            out.write("# " + line + "\n")
        base = 0
        for v, f in parts:
            for p in v:
                out.write("v %.4f %.4f %.4f\n" % p)
            for face in f:
                out.write("f " + " ".join(str(base + i + 1) for i in face) + "\n")
            base += len(v)


def pyramid(cx, cy, side, height):
    h = side / 2.0
    v = [(cx - h, cy - h, 0.0), (cx + h, cy - h, 0.0), (cx + h, cy + h, 0.0), (cx - h, cy + h, 0.0),
         (cx, cy, height)]
    f = [(0, 3, 2, 1), (0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]
    return v, f


def cup(cx, cy, r_out, r_in, height, bottom, n=48):
    """An open cylinder cup: outer wall, inner wall, rim ring, inner floor, base."""
    v, f = [], []
    ring = lambda r, z: [(cx + r * math.cos(2 * math.pi * k / n), cy + r * math.sin(2 * math.pi * k / n), z)
                         for k in range(n)]
    ob, ot, it, ib = ring(r_out, 0.0), ring(r_out, height), ring(r_in, height), ring(r_in, bottom)
    v = ob + ot + it + ib + [(cx, cy, 0.0), (cx, cy, bottom)]
    OB, OT, IT, IB, CB, CI = 0, n, 2 * n, 3 * n, 4 * n, 4 * n + 1
    for k in range(n):
        j = (k + 1) % n
        f.append((OB + k, OB + j, OT + j, OT + k))   # outer wall, facing out
        f.append((OT + k, OT + j, IT + j, IT + k))   # rim, facing up
        f.append((IT + k, IT + j, IB + j, IB + k))   # inner wall, facing the axis
        f.append((IB + k, IB + j, CI))               # inner floor, facing up
        f.append((OB + j, OB + k, CB))               # base, facing down
    return v, f


def spoon(x0, y0, z_bowl, length, n=24):
    """A spoon across the cup's mouth: a shallow elliptic bowl (concave up) and
    a flat handle, along +x from the bowl's centre (x0, y0)."""
    v, f = [], []
    a, b, depth = 22.0, 14.0, 6.0
    rings = 6
    # bowl surface (upper side), rings of ellipses going down to the centre
    centre = len(v)
    v.append((x0, y0, z_bowl - depth))
    for r in range(1, rings + 1):
        s = r / rings
        z = z_bowl - depth * (1 - s * s)
        for k in range(n):
            t = 2 * math.pi * k / n
            v.append((x0 + a * s * math.cos(t), y0 + b * s * math.sin(t), z))
    for k in range(n):
        j = (k + 1) % n
        f.append((centre, 1 + j, 1 + k)[::-1])
    for r in range(1, rings):
        o0, o1 = 1 + (r - 1) * n, 1 + r * n
        for k in range(n):
            j = (k + 1) % n
            f.append((o0 + k, o1 + k, o1 + j, o0 + j)[::-1])
    # underside: a copy 1.5 mm lower, faces reversed
    under = len(v)
    for p in v[:under]:
        v.append((p[0], p[1], p[2] - 1.5))
    for face in list(f):
        f.append(tuple(under + i for i in face[::-1]))
    # handle: a thin box from the bowl's rim along +x, sloping down 8 mm
    hv, hf = box(0.0, -4.0, -1.5, length, 4.0, 0.0)
    hx0 = x0 + a - 2.0
    slope = -8.0 / length
    base = len(v)
    for (x, y, z) in hv:
        v.append((hx0 + x, y0 + y, z_bowl + z + slope * x))
    for face in hf:
        f.append(tuple(base + i for i in face))
    return v, f


if __name__ == "__main__":
    write("flat_plate.obj", """
Paper 004 section 5's flat surface: a plate 300 x 300 x 20 mm centred on the
table's origin (top face z = 20 mm). The random-error benchmark scans it with
parallel stripes.""", [box(-150.0, -150.0, 0.0, 150.0, 150.0, 20.0)])
    write("pyramid.obj", """
Paper 004 section 5's pyramid: square base 120 mm on the table centred at the
origin, apex (0, 0, 60) mm (faces at 45 deg). The direction-dependent error is
the shift of the apex located from scans in different directions.""", [pyramid(0.0, 0.0, 120.0, 60.0)])
    write("cup_spoon.obj", """
Paper 004 figure 4-1: a coffee cup (outer radius 40 mm, wall 4 mm, 90 mm tall,
floor 6 mm) at the origin with a spoon resting across its mouth: the bowl
over the cup (centre (-10, 0), rim height 95 mm) and the handle along +x,
120 mm long, sloping down 8 mm.""", [cup(0.0, 0.0, 40.0, 36.0, 90.0, 6.0), spoon(-10.0, 0.0, 95.0, 120.0)])

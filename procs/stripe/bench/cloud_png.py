#!/usr/bin/env python3
"""A picture of a light-stripe cloud (PLY from ephor-stripe-range, mm, table
frame) as a PNG, with nothing but the standard library: the points seen in
perspective from above and in front (the paper's figure 4-1 was a perspective
view of the cup and spoon), coloured by height, each stripe a row of dots.

    python3 procs/stripe/bench/cloud_png.py CLOUD.ply OUT.png [--size 640x480]
        [--azimuth-deg -60] [--elevation-deg 35] [--distance-mm 700]
"""
import argparse
import math
import struct
import sys
import zlib


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii", "replace").splitlines()
    if "format binary_little_endian 1.0" not in header:
        sys.exit(f"{path}: not a binary little-endian PLY")
    n = next(int(l.split()[2]) for l in header if l.startswith("element vertex"))
    props = [l.split()[2] for l in header if l.startswith("property")]
    if props[:3] != ["x", "y", "z"] or any(l.split()[1] != "float" for l in header if l.startswith("property")):
        sys.exit(f"{path}: want float x y z properties")
    stride = 4 * len(props)
    return [struct.unpack_from("<3f", data, end + i * stride) for i in range(n)]


def write_png(path, width, height, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    open(path, "wb").write(png)


def colour(t):
    # Low blue -> green -> yellow -> red high.
    stops = [(0.0, (40, 70, 200)), (0.35, (40, 190, 120)), (0.7, (240, 220, 40)), (1.0, (230, 50, 40))]
    for (a, ca), (b, cb) in zip(stops, stops[1:]):
        if t <= b:
            u = (t - a) / (b - a) if b > a else 0.0
            return tuple(int(ca[k] + u * (cb[k] - ca[k])) for k in range(3))
    return stops[-1][1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("cloud")
    ap.add_argument("out")
    ap.add_argument("--size", default="640x480")
    ap.add_argument("--azimuth-deg", type=float, default=-60.0)
    ap.add_argument("--elevation-deg", type=float, default=35.0)
    ap.add_argument("--distance-mm", type=float, default=700.0)
    a = ap.parse_args()
    w, h = (int(v) for v in a.size.split("x"))
    pts = read_ply(a.cloud)
    if not pts:
        sys.exit(f"{a.cloud}: no points")
    cx = sum(p[0] for p in pts) / len(pts)
    cy = sum(p[1] for p in pts) / len(pts)
    zs = sorted(p[2] for p in pts)
    z0, z1 = zs[int(0.01 * (len(zs) - 1))], zs[int(0.99 * (len(zs) - 1))]
    az, el = math.radians(a.azimuth_deg), math.radians(a.elevation_deg)
    # Camera looking at (cx, cy, 0) from the azimuth and elevation given.
    fwd = (-math.cos(el) * math.cos(az), -math.cos(el) * math.sin(az), -math.sin(el))
    right = (-math.sin(az), math.cos(az), 0.0)
    up = (right[1] * fwd[2] - right[2] * fwd[1], right[2] * fwd[0] - right[0] * fwd[2], right[0] * fwd[1] - right[1] * fwd[0])
    eye = (cx - a.distance_mm * fwd[0], cy - a.distance_mm * fwd[1], -a.distance_mm * fwd[2])
    f = 1.1 * w
    img = [[(250, 250, 250)] * w for _ in range(h)]
    depth = [[1e18] * w for _ in range(h)]
    for p in pts:
        d = (p[0] - eye[0], p[1] - eye[1], p[2] - eye[2])
        zc = d[0] * fwd[0] + d[1] * fwd[1] + d[2] * fwd[2]
        if zc <= 1.0:
            continue
        u = w / 2 + f * (d[0] * right[0] + d[1] * right[1] + d[2] * right[2]) / zc
        v = h / 2 - f * (d[0] * up[0] + d[1] * up[1] + d[2] * up[2]) / zc
        c = colour(min(1.0, max(0.0, (p[2] - z0) / max(1e-6, z1 - z0))))
        for du in (0, 1):
            for dv in (0, 1):
                x, y = int(u) + du, int(v) + dv
                if 0 <= x < w and 0 <= y < h and zc < depth[y][x]:
                    depth[y][x] = zc
                    img[y][x] = c
    write_png(a.out, w, h, [[ch for px in row for ch in px] for row in img])
    print(f"{a.out}: {len(pts)} points, heights {z0:.1f}-{z1:.1f} mm coloured blue to red")


if __name__ == "__main__":
    main()

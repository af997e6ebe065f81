#!/usr/bin/env python3
"""Writes one organized ascii PCD sequence in the number spellings of several writers (issue #38,
item 3; docs/FORMAT.md 14.6), one folder per convention:

  pcl/       floats "%.8g" (PCL's writer), integers "%d", NaN "nan"
  repr/      Python's repr of each float32 widened to a double ("-0.059286266565322876"), "nan"
  f32/       the shortest text that gives back the float32, in Python's layout (numpy's str of a
             float32: "-0.05928627", "1e-05", "3.0"), integers "%d", "nan"
  savetxt/   numpy savetxt's default "%.18e" for the float columns, "%d" for the integer ones
             (PCL's reader, which capz reads through, takes "5.9e+06" in an integer field as 5)
  fixed/     floats "%.6f", integers "%d", NaN spelled "NaN"
  open3d/    Open3D's legacy writer: "%.10g" (rgb as the float whose bits are the packed colour,
             TYPE F), integers "%d", "nan"

The scene: a synthetic depth camera (W x H pixels, 525 px focal length) looking at a wall 3 m
away and a ball of 0.4 m radius crossing the view, frame after frame; pixels whose ray hits
nothing within 4 m, and a seeded 3% of dropouts, are misses: x y z and the normals NaN, rgb 0,
intensity 0, label 0. Fields: x y z (F4), rgb (U4 packed 0x00RRGGBB; F4 in open3d/), intensity
(F4), normal_x normal_y normal_z (F4), label (U2: 1 wall, 2 ball). Seeded: running this again
writes the same bytes. Standard library only.

usage: python3 data/make_ascii_pcd.py OUTDIR [--width 160 --height 120 --frames 8]
"""
import argparse
import math
import os
import random
import struct


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def rgb_as_float(u):
    return struct.unpack("<f", struct.pack("<I", u))[0]


def shortest_f32(v):
    """The shortest decimal reading back as float32 v, in Python's repr layout."""
    for p in range(1, 10):
        s = "%.*e" % (p - 1, v)
        if f32(float(s)) == v:
            return repr(float(s))
    return repr(v)


def scene(w, h, frame, rng):
    """Points of one frame: tuples (x, y, z, rgb, intensity, nx, ny, nz, label), NaN misses."""
    fx = 525.0 * w / 640.0
    cx, cy = (w - 1) / 2.0, (h - 1) / 2.0
    bx, by, bz, br = -0.9 + 0.25 * frame, 0.1 * math.sin(frame), 2.2, 0.4
    pts = []
    nan = float("nan")
    for v in range(h):
        for u in range(w):
            dx, dy = (u - cx) / fx, (v - cy) / fx
            n = math.sqrt(dx * dx + dy * dy + 1)
            d = (dx / n, dy / n, 1 / n)
            # The ball: |t d - c|^2 = r^2.
            b = d[0] * bx + d[1] * by + d[2] * bz
            disc = b * b - (bx * bx + by * by + bz * bz - br * br)
            hit = None
            if disc >= 0:
                t = b - math.sqrt(disc)
                p = (t * d[0], t * d[1], t * d[2])
                nrm = ((p[0] - bx) / br, (p[1] - by) / br, (p[2] - bz) / br)
                hit = (p, nrm, 2, (200, 40 + (u * 3) % 60, 30))
            elif abs(dx) < 1.2:
                t = 3.0 / d[2]
                if t < 4.0:
                    p = (t * d[0], t * d[1], 3.0)
                    hit = (p, (0.0, 0.0, -1.0), 1, (90 + v % 40, 110, 120 + u % 50))
            if hit is None or rng.random() < 0.03:
                pts.append((nan, nan, nan, 0, 0.0, nan, nan, nan, 0))
                continue
            p, nrm, label, c = hit
            noise = 0.002 * (rng.random() - 0.5)
            z = p[2] + noise
            s = z / p[2]
            rgb = (c[0] << 16) | (c[1] << 8) | c[2]
            inten = f32(0.25 + 0.5 * abs(nrm[2]) + 0.01 * rng.random())
            pts.append((f32(p[0] * s), f32(p[1] * s), f32(z), rgb, inten, f32(nrm[0]),
                        f32(nrm[1]), f32(nrm[2]), label))
    return pts


def spell(conv, pt):
    x, y, z, rgb, inten, nx, ny, nz, label = pt
    floats = (x, y, z)
    nan_text = "NaN" if conv == "fixed" else "nan"

    def fl(v):
        if math.isnan(v):
            return nan_text
        if conv == "pcl":
            return "%.8g" % v
        if conv == "repr":
            return repr(v)
        if conv == "f32":
            return shortest_f32(v)
        if conv == "savetxt":
            return "%.18e" % v
        if conv == "fixed":
            return "%.6f" % v
        return "%.10g" % v  # open3d

    def it(v):
        return "%d" % v

    colour = "%.10g" % rgb_as_float(rgb) if conv == "open3d" else it(rgb)
    fields = [fl(v) for v in floats] + [colour, fl(inten)] + [fl(v) for v in (nx, ny, nz)] + \
        [it(label)]
    return " ".join(fields)


def header(conv, w, h):
    rgb_type = "F" if conv == "open3d" else "U"
    return ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
            "FIELDS x y z rgb intensity normal_x normal_y normal_z label\n"
            "SIZE 4 4 4 4 4 4 4 4 2\nTYPE F F F %s F F F F U\nCOUNT 1 1 1 1 1 1 1 1 1\n"
            "WIDTH %d\nHEIGHT %d\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA ascii\n"
            % (rgb_type, w, h, w * h))


CONVENTIONS = ["pcl", "repr", "f32", "savetxt", "fixed", "open3d"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--width", type=int, default=160)
    ap.add_argument("--height", type=int, default=120)
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--only", choices=CONVENTIONS, action="append")
    args = ap.parse_args()
    rng = random.Random(38)
    frames = [scene(args.width, args.height, f, rng) for f in range(args.frames)]
    for conv in args.only or CONVENTIONS:
        d = os.path.join(args.out, conv)
        os.makedirs(d, exist_ok=True)
        for f, pts in enumerate(frames):
            text = header(conv, args.width, args.height) + \
                "".join(spell(conv, p) + "\n" for p in pts)
            with open(os.path.join(d, "frame_%04d.pcd" % f), "w", newline="\n") as out:
                out.write(text)
        print(d)


if __name__ == "__main__":
    main()

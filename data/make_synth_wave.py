#!/usr/bin/env python3
"""Writes data/synth_wave/: a small synthetic mesh-like point-cloud sequence, made for tests.

A 16 x 16 grid of vertices (256 points) on a sheet 1.0 unit wide, over 60 frames: a travelling
wave bends the sheet (amplitude 0.08, wavelength 0.7, period 30 frames) while the whole sheet
turns about the vertical axis (0.01 rad a frame) and drifts along x (0.005 a frame). Every
frame is a binary PCD file (x y z float32, little endian) named frame_0001.pcd ... frame_0060.pcd,
in the layout of the shared PCD sequences. Nothing random: running this again writes the same
bytes (float32 rounding of IEEE double sin/cos).

usage: python3 data/make_synth_wave.py [OUT_DIR]   (default: data/synth_wave next to this file)
"""
import math
import os
import struct
import sys

SIDE, FRAMES = 16, 60
HEADER = (
    "# .PCD v0.7 - Point Cloud Data file format\n"
    "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
    "WIDTH {n}\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA binary\n"
)


def frame_points(f):
    """The 256 (x, y, z) vertices of frame f (0-based)."""
    turn = 0.01 * f
    c, s = math.cos(turn), math.sin(turn)
    pts = []
    for i in range(SIDE):
        for j in range(SIDE):
            u, v = i / (SIDE - 1), j / (SIDE - 1)
            z = 0.08 * math.sin(2 * math.pi * (u / 0.7 - f / 30.0)) * (0.5 + v)
            x0, y0 = u - 0.5, v - 0.5
            pts.append((c * x0 - s * y0 + 0.005 * f, s * x0 + c * y0, z))
    return pts


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "synth_wave")
    os.makedirs(out, exist_ok=True)
    for f in range(FRAMES):
        pts = frame_points(f)
        body = b"".join(struct.pack("<3f", *p) for p in pts)
        with open(os.path.join(out, "frame_%04d.pcd" % (f + 1)), "wb") as fh:
            fh.write(HEADER.format(n=len(pts)).encode("ascii") + body)


if __name__ == "__main__":
    main()

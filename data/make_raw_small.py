#!/usr/bin/env python3
"""Writes the golden sources of format 1.1's raw windows (docs/FORMAT.md "Raw windows"):

- depth_drop_small/: a synthetic depth camera's frames with the invalid pixels dropped, as a
  pipeline that removes NaN points writes them: 3 binary PCD frames of x y z (F4) from a 64 x 48
  pinhole camera (fx = fy = 52, principal point at the centre) looking at a wall at 3.5 m, a floor
  1.2 m below it, a box and a sphere, the camera sliding 1 cm a frame; depth on a millimetre grid
  (z = mm / 1000 as float32, x = (u - cx) z / fx and y = (v - cy) z / fy as float32), depth noise
  of up to 2 z^2 mm, and every pixel beyond 4 m, nearer than 0.4 m, or drawn with probability
  0.03 left out. The scan coder has no pinhole model: its windows cost more than LZMA2 of the
  bits, so the encoder keeps them raw.
- utm_small/: data/lidar_small's first 3 sweeps (x y z intensity) without their NaN points
  (frames of their own counts) moved to map coordinates, (500000.123456789, 4000000.987654321,
  100.5) m added, and written with x y z as float64 (F8) and intensity F4: coordinates on no
  decimal grid and not float32, which a lossless archive keeps as float64 bits (mode 3).

Deterministic, standard library only.

usage: python3 data/make_raw_small.py
       python3 data/make_raw_small.py --depth OUT [--width 640 --height 480 --frames 5]
The second form writes only the depth frames, at another size (the focal length scaled with the
width: 52 at 64 pixels), into OUT: the larger input of docs/BENCHMARKS.md "Raw windows".
"""
import argparse
import math
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def pcd(path, fields, rows):
    """A binary PCD of (name, type, size) fields and rows of values."""
    n = len(rows)
    head = ('# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n'
            'FIELDS %s\nSIZE %s\nTYPE %s\nCOUNT %s\nWIDTH %d\nHEIGHT 1\n'
            'VIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA binary\n') % (
        ' '.join(f[0] for f in fields), ' '.join(str(f[2]) for f in fields),
        ' '.join(f[1] for f in fields), ' '.join('1' for _ in fields), n, n)
    fmt = '<' + ''.join({('F', 4): 'f', ('F', 8): 'd'}[(f[1], f[2])] for f in fields)
    with open(path, 'wb') as out:
        out.write(head.encode('ascii'))
        for r in rows:
            out.write(struct.pack(fmt, *r))


def f32(v):
    return struct.unpack('<f', struct.pack('<f', v))[0]


def depth(frame, rng, w=64, h=48, f=52.0):
    """The valid pixels of one depth frame as float32 (x, y, z) rows."""
    cx, cy, shift = (w - 1) / 2, (h - 1) / 2, 0.01 * frame
    rows = []
    for v in range(h):
        for u in range(w):
            dx, dy = (u - cx) / f, (v - cy) / f
            z = 3.5 + shift
            if dy > 0:
                z = min(z, 1.2 / dy)
            if abs(2 * dx - 0.3 - shift) < 0.25 and abs(2 * dy) < 0.3:
                z = min(z, 2.0)
            n = math.sqrt(dx * dx + dy * dy + 1)  # a sphere of 0.35 m at (-0.5 + shift, 0.1, 1.6)
            c = (-0.5 + shift, 0.1, 1.6)
            b = (c[0] * dx + c[1] * dy + c[2]) / n
            disc = b * b - (c[0] ** 2 + c[1] ** 2 + c[2] ** 2 - 0.35 ** 2)
            if disc > 0:
                z = min(z, (b - math.sqrt(disc)) / n)
            mm = round(z * 1000 + rng.uniform(-2, 2) * z * z)
            if mm > 4000 or mm <= 400 or rng.random() < 0.03:
                continue
            zf = f32(mm / 1000)
            rows.append((f32((u - cx) * zf / f), f32((v - cy) * zf / f), zf))
    return rows


def read_xyzi(path):
    """(x, y, z, intensity) rows of a lidar_small frame (binary PCD, x y z intensity first)."""
    b = open(path, 'rb').read()
    pos, head = 0, {}
    while True:
        e = b.index(b'\n', pos)
        key, _, rest = b[pos:e].decode('ascii').partition(' ')
        pos = e + 1
        head[key] = rest.split()
        if key == 'DATA':
            break
    size = sum(int(s) * int(c) for s, c in zip(head['SIZE'], head['COUNT']))
    n = int(head['POINTS'][0])
    return [struct.unpack_from('<ffff', b, pos + i * size) for i in range(n)]


def depth_frames(out, frames, w, h):
    """`frames` depth frames of w x h pixels into folder out."""
    rng = random.Random(7)
    os.makedirs(out, exist_ok=True)
    xyz = [('x', 'F', 4), ('y', 'F', 4), ('z', 'F', 4)]
    for k in range(frames):
        pcd(os.path.join(out, 'depth_%02d.pcd' % k), xyz, depth(k, rng, w, h, 52.0 * w / 64))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--depth')
    ap.add_argument('--width', type=int, default=640)
    ap.add_argument('--height', type=int, default=480)
    ap.add_argument('--frames', type=int, default=5)
    a = ap.parse_args()
    if a.depth:
        depth_frames(a.depth, a.frames, a.width, a.height)
        return
    depth_frames(os.path.join(HERE, 'depth_drop_small'), 3, 64, 48)
    out = os.path.join(HERE, 'utm_small')
    os.makedirs(out, exist_ok=True)
    off = (500000.123456789, 4000000.987654321, 100.5)
    for k in range(3):
        rows = read_xyzi(os.path.join(HERE, 'lidar_small', 'sweep_%05d.pcd' % k))
        rows = [(x + off[0], y + off[1], z + off[2], i) for x, y, z, i in rows
                if not math.isnan(x + y + z)]
        pcd(os.path.join(out, 'utm_%02d.pcd' % k), [('x', 'F', 8), ('y', 'F', 8), ('z', 'F', 8),
                                                    ('intensity', 'F', 4)], rows)


if __name__ == '__main__':
    main()

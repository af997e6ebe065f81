#!/usr/bin/env python3
"""Makes a synthetic sequence of organized LiDAR sweeps (binary PCD frames, WIDTH columns x
HEIGHT beams, as Ouster's ROS driver writes them) from one real unorganized sweep: the sweep's
points binned into a beams x columns grid by elevation rank and azimuth (the nearest point of a
cell kept), a cell without a point a no-return point (NaN, or 0 0 0 as Ouster writes it).

Two motions (docs/lab/2026-11-30-fixed-count-scans.md):
- turning (the default): the scene is fixed and the sensor turns --turn columns a frame (frame f
  is the grid rolled by turn x f columns), so a point moves to another index from frame to frame;
- still (--still-noise S): the grid stays, every point's range scaled by 1 + N(0, S) / range
  (S metres of range noise) each frame.
With --fields ouster the frames carry the fields of Ouster's driver (intensity F4, t U4,
reflectivity U2, ring U2, ambient U2, range U4, and its padding); else x y z alone.

Usage (numpy; /usr/bin/python3):
    tools/make_organized_scans.py ../shared/data/scan/single/hesai-64.pcd OUT
        [--frames 5] [--beams 64] [--columns 1024] [--turn 3 | --still-noise 0.005]
        [--gap nan|zero] [--fields ouster|none] [--seed 1]
"""
import argparse
import os

import numpy as np

from make_scan_sequences import read_pcd_xyz


def read_sweep(path):
    """The finite points of a PCD frame as float32 x y z (make_scan_sequences.py's reader)."""
    pts = read_pcd_xyz(path).astype(np.float32)
    return pts[np.isfinite(pts).all(1)]


def grid_of(pts, beams, columns):
    """beams x columns x 3 float32 grid and its no-return mask (True: no point)."""
    az = np.arctan2(pts[:, 1], pts[:, 0])
    r = np.linalg.norm(pts, axis=1)
    el = np.arcsin(pts[:, 2] / np.maximum(r, 1e-9))
    col = ((az + np.pi) / (2 * np.pi) * columns).astype(int) % columns
    order = np.argsort(el, kind='stable')
    ring = np.empty(len(el), int)
    ring[order] = np.arange(len(el)) * beams // len(el)
    grid = np.zeros((beams, columns, 3), np.float32)
    best = np.full((beams, columns), np.inf)
    for k in range(len(pts)):
        if r[k] < best[ring[k], col[k]]:
            best[ring[k], col[k]] = r[k]
            grid[ring[k], col[k]] = pts[k]
    return grid, ~np.isfinite(best)


def ouster_record(g, beams, columns):
    rec = np.zeros((beams, columns), dtype=[
        ('x', '<f4'), ('y', '<f4'), ('z', '<f4'), ('_', '<f4'), ('intensity', '<f4'),
        ('t', '<u4'), ('reflectivity', '<u2'), ('ring', '<u2'), ('ambient', '<u2'),
        ('_2', '<u2'), ('range', '<u4')])
    rec['x'], rec['y'], rec['z'] = g[:, :, 0], g[:, :, 1], g[:, :, 2]
    rr = np.linalg.norm(g, axis=2)
    rr[~np.isfinite(rr)] = 0
    rec['range'] = (rr * 1000).astype(np.uint32)
    rec['intensity'] = np.where(rr > 0, np.round(100 + 50 * np.sin(rr)), 0).astype(np.float32)
    rec['reflectivity'] = (rec['intensity'] / 2).astype(np.uint16)
    rec['ring'] = np.arange(beams)[:, None]
    rec['t'] = (np.arange(columns)[None, :] * 97656).astype(np.uint32)
    rec['ambient'] = (np.arange(columns)[None, :] % 37 + np.arange(beams)[:, None]).astype(np.uint16)
    head = ('FIELDS x y z _ intensity t reflectivity ring ambient _ range\n'
            'SIZE 4 4 4 1 4 4 2 2 2 1 4\nTYPE F F F U F U U U U U U\n'
            'COUNT 1 1 1 4 1 1 1 1 1 2 1\n')
    return head, rec.tobytes()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('sweep')
    ap.add_argument('out')
    ap.add_argument('--frames', type=int, default=5)
    ap.add_argument('--beams', type=int, default=64)
    ap.add_argument('--columns', type=int, default=1024)
    ap.add_argument('--turn', type=int, default=3)
    ap.add_argument('--still-noise', type=float, default=0.0)
    ap.add_argument('--gap', choices=['nan', 'zero'], default='nan')
    ap.add_argument('--fields', choices=['ouster', 'none'], default='ouster')
    ap.add_argument('--seed', type=int, default=1)
    a = ap.parse_args()
    H, W = a.beams, a.columns
    grid, empty = grid_of(read_sweep(a.sweep), H, W)
    rng = np.random.default_rng(a.seed)
    os.makedirs(a.out, exist_ok=True)
    for f in range(a.frames):
        if a.still_noise > 0:
            r = np.where(empty, 1.0, np.linalg.norm(grid, axis=2))
            scale = 1 + rng.normal(0, a.still_noise, (H, W)) / np.maximum(r, 0.5)
            g, gap = (grid * scale[:, :, None]).astype(np.float32), empty
        else:
            g, gap = np.roll(grid, a.turn * f, axis=1), np.roll(empty, a.turn * f, axis=1)
        g[gap] = np.nan if a.gap == 'nan' else 0
        if a.fields == 'ouster':
            fields, body = ouster_record(g, H, W)
        else:
            fields = 'FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n'
            body = g.astype('<f4').tobytes()
        head = ('# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n' + fields +
                f'WIDTH {W}\nHEIGHT {H}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {W * H}\nDATA binary\n')
        open(os.path.join(a.out, f'{f:04d}.pcd'), 'wb').write(head.encode() + body)
    print(f'{a.out}: {a.frames} frames of {H} x {W}, {int((~empty).sum())} points with a return')


if __name__ == '__main__':
    main()

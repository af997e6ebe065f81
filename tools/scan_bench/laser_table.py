#!/usr/bin/python3
"""Infers a spinning LiDAR's laser table from its sweeps (issue #37): per laser the tangent of
its elevation, its z offset and its points per turn, as G-PCC's angular mode wants them.

  laser_table.py FRAME.pcd|FOLDER [...] [--step S] [--json]

Model: a laser l fires on the cone z = z_l + r tan(theta_l), r = sqrt(x^2 + y^2) (sensor at
the origin; RoboSense's z_l grow with the elevation). The lasers are found
  - from a ring / channel field where the file has one with at least two values: the points of
    each value are one laser;
  - else by clustering elevations: a histogram of atan2(z, r) over the points beyond 0.5 m at
    0.02 degrees (smoothed over three bins), each peak holding at least 0.02% of those points
    one laser (drivers' points often sit exactly on the cones; peaks closer than 0.05 degree
    merge); then every point goes to the laser whose cone is nearest in z and the cones are
    refitted, three times.
Each laser's (tan theta, z) is a least-squares line z = z + r t over its points (trimmed of
outliers at 4 median deviations, twice). Points per turn: 2 pi over the median azimuth step
between a laser's consecutive distinct azimuths in each frame (the step is the sensor's firing
period; gaps where nothing returned are longer and fall above the median).

Prints the table (ascending tan theta) and, with --step S, the TMC13 options that code the
integers round(x / S) losslessly with the angular predictive tree (lasersZ = -z / S).
"""
import argparse
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pcd  # noqa: E402

RING_FIELDS = ('ring', 'channel', 'laser_id', 'laser')


def _fit_cone(r, z):
    """(tan theta, z offset) of z = z0 + r t, trimmed twice at 4 median deviations."""
    keep = np.ones(len(r), bool)
    t = z0 = 0.0
    for _ in range(3):
        if keep.sum() < 2 or np.ptp(r[keep]) < 1e-6:
            t = float(np.median(z[keep] / np.maximum(r[keep], 1e-9))) if keep.any() else 0.0
            return t, 0.0
        A = np.stack([r[keep], np.ones(keep.sum())], axis=1)
        (t, z0), *_ = np.linalg.lstsq(A, z[keep], rcond=None)
        res = np.abs(z - z0 - r * t)
        mad = np.median(res[keep]) + 1e-9
        keep = res <= 4 * mad * 1.4826 + 1e-6
    return float(t), float(z0)


def _assign(r, z, tans, offs):
    """Index of the cone nearest in z to each point."""
    pred = offs[None, :] + r[:, None] * tans[None, :]
    return np.argmin(np.abs(z[:, None] - pred), axis=1)


def _cluster_elevations(r, z):
    far = r > 0.5
    if far.sum() < 100:
        far = r > np.median(r)
    elev = np.degrees(np.arctan2(z[far], r[far]))
    lo, hi = elev.min() - 0.1, elev.max() + 0.1
    hist, edges = np.histogram(elev, bins=max(int((hi - lo) / 0.02), 1), range=(lo, hi))
    sm = np.convolve(hist, np.ones(3) / 3, mode="same")
    floor = max(5.0, 0.0002 * far.sum())
    peaks = [i for i in range(1, len(sm) - 1)
             if sm[i] >= sm[i - 1] and sm[i] > sm[i + 1] and sm[i] >= floor]
    # merge peaks closer than 0.1 degree, keeping the higher
    merged = []
    for i in peaks:
        if merged and (i - merged[-1]) * 0.02 < 0.05:
            if sm[i] > sm[merged[-1]]:
                merged[-1] = i
        else:
            merged.append(i)
    centres = np.radians((edges[np.array(merged)] + edges[np.array(merged) + 1]) / 2)
    return np.tan(centres)


def _points_per_turn(frames_xy):
    """2 pi over the median step between consecutive distinct azimuths, over frames."""
    steps = []
    for xy in frames_xy:
        if len(xy) < 8:
            continue
        az = np.sort(np.arctan2(xy[:, 1], xy[:, 0]))
        d = np.diff(az)
        d = d[d > 1e-6]
        if len(d):
            steps.append(np.median(d))
    if not steps:
        return 0
    return int(round(2 * math.pi / float(np.median(steps))))


def infer(frames, rings=None):
    """frames: list of (n, 3) arrays (metres); rings: matching list of int arrays or None.
    Returns a list of dicts (tan, z, points_per_turn, points), ascending tan."""
    xyz = np.concatenate(frames).astype(np.float64)
    ok = np.isfinite(xyz).all(axis=1)
    r_all = np.hypot(xyz[:, 0], xyz[:, 1])
    ok &= r_all > 0.3
    frame_id = np.concatenate([np.full(len(f), k) for k, f in enumerate(frames)])
    r, z = r_all[ok], xyz[ok, 2]
    if rings is not None:
        ring = np.concatenate(rings)[ok]
        labels = np.unique(ring)
        lab = np.searchsorted(labels, ring)
        cones = [_fit_cone(r[lab == k], z[lab == k]) for k in range(len(labels))]
        tans = np.array([c[0] for c in cones])
        offs = np.array([c[1] for c in cones])
    else:
        tans = _cluster_elevations(r, z)
        offs = np.zeros(len(tans))
        for _ in range(3):
            lab = _assign(r, z, tans, offs)
            cones = [_fit_cone(r[lab == k], z[lab == k]) if (lab == k).sum() >= 2
                     else (tans[k], offs[k]) for k in range(len(tans))]
            tans = np.array([c[0] for c in cones])
            offs = np.array([c[1] for c in cones])
        lab = _assign(r, z, tans, offs)
    fid = frame_id[ok]
    xy = xyz[ok, :2]
    table = []
    for k in range(len(tans)):
        sel = lab == k
        if sel.sum() < 2:
            continue
        ppt = _points_per_turn([xy[sel & (fid == f)] for f in np.unique(fid[sel])])
        table.append({'tan': float(tans[k]), 'z': float(offs[k]),
                      'points_per_turn': max(ppt, 1), 'points': int(sel.sum())})
    table.sort(key=lambda e: e['tan'])
    return table


def tmc13_options(table, step):
    """TMC13 options for lossless angular predictive geometry on the grid of `step`."""
    ppt = max(e['points_per_turn'] for e in table)
    return ['--geomTreeType=1', '--angularEnabled=1', '--numLasers=%d' % len(table),
            '--lasersTheta=' + ','.join('%.7f' % e['tan'] for e in table),
            '--lasersZ=' + ','.join('%.4f' % (-e['z'] / step) for e in table),
            '--lasersNumPhiPerTurn=' + ','.join(str(e['points_per_turn']) for e in table),
            '--lidarHeadPosition=0,0,0', '--positionAzimuthScaleLog2=12',
            '--positionAzimuthSpeed=%d' % max(1, round(2 ** 24 / ppt)),
            '--positionQuantisationEnabled=0']


def read_sequence(paths):
    """Frames (x y z float32, finite points) and ring arrays (or None) of PCD files/folders."""
    files = []
    for p in paths:
        if os.path.isdir(p):
            files += sorted(os.path.join(p, f) for f in os.listdir(p) if f.endswith('.pcd'))
        else:
            files.append(p)
    frames, rings = [], []
    for f in files:
        xyz, arrays = pcd.read_xyz(f)
        ok = np.isfinite(xyz).all(axis=1)
        frames.append(xyz[ok])
        ring = next((arrays[n] for n in RING_FIELDS if n in arrays), None)
        rings.append(None if ring is None else ring[ok].astype(np.int64))
    if any(r is None for r in rings) or len(np.unique(np.concatenate(rings))) < 2:
        rings = None
    return frames, rings


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('paths', nargs='+')
    ap.add_argument('--step', type=float, help='grid step (metres): print TMC13 options')
    ap.add_argument('--json', action='store_true')
    a = ap.parse_args()
    frames, rings = read_sequence(a.paths)
    table = infer(frames, rings)
    if a.json:
        print(json.dumps(table))
    else:
        print('# %d lasers (%s)' % (len(table), 'ring field' if rings else 'clustered'))
        print('laser\ttan_theta\televation_deg\tz_m\tpoints_per_turn\tpoints')
        for k, e in enumerate(table):
            print('%d\t%.6f\t%.3f\t%.4f\t%d\t%d' % (k, e['tan'], math.degrees(math.atan(e['tan'])),
                                                     e['z'], e['points_per_turn'], e['points']))
    if a.step:
        print(' '.join(tmc13_options(table, a.step)))


if __name__ == '__main__':
    main()

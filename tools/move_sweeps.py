#!/usr/bin/env python3
"""Makes a moving sensor's sweeps from a still sensor's: sweep f of a scan folder seen again from
f x SPEED metres along x (a platform driving at SPEED metres a sweep through a still scene), by
the same lasers. Each point of sweep f is taken relative to the moved sensor and cast into its
ring x column image (the ring of the nearest laser elevation, found per ring field value from the
data; columns of STEP degrees); the nearest point of a cell hides the others, an empty cell takes
the nearest of its two neighbours' points, and each kept cell gives one point on its laser's ray
(the ring's elevation, the column's azimuth) at the kept point's distance, as a driver computes
points from a range image. Cells are written ring by ring, column by column. Writes binary PCD
frames of x y z (float32) under the sources' names (docs/lab/2026-11-30-moves.md).

What a move hides, shows or leaves unseen differs from a real drive: the scene is only what the
still sensor saw (its shadows stay empty), and a translated point lands between the lasers'
cones where a real one would be measured on them.

Usage (numpy and capz's Python module; /usr/bin/python3):
    PYTHONPATH=build/python:tools /usr/bin/python3 tools/move_sweeps.py \\
        ../shared/data/scan/pandar64-factory20 OUT [--speed 0.3] [--step 0.2]
"""
import argparse
import os

import numpy as np

from turn_sweeps import read_sweeps, write_xyz


def ring_elevations(xyz, ring):
    """Per ring field value (0 .. max), the median elevation of its points (radians)."""
    el = np.arctan2(xyz[:, 2], np.hypot(xyz[:, 0], xyz[:, 1]))
    out = np.full(int(ring.max()) + 1, np.nan)
    for k in np.unique(ring):
        out[k] = np.median(el[ring == k])
    return out


def render(p, elev, step, columns):
    """The points p (sensor coordinates) as the lasers of elevations elev see them: x y z a kept
    cell, ring by ring."""
    rho = np.hypot(p[:, 0], p[:, 1])
    dist = np.sqrt(rho * rho + p[:, 2] ** 2)
    el = np.arctan2(p[:, 2], rho)
    order = np.argsort(elev)
    sorted_el = elev[order]
    at = np.clip(np.searchsorted(sorted_el, el), 1, len(sorted_el) - 1)
    nearer = np.where(np.abs(el - sorted_el[at - 1]) < np.abs(el - sorted_el[at]), at - 1, at)
    ring = order[nearer]
    spacing = np.median(np.diff(sorted_el))
    ok = np.abs(el - elev[ring]) <= spacing / 2
    col = np.round(np.arctan2(p[:, 1], p[:, 0]) / step).astype(np.int64) % columns
    K = len(elev)
    best = np.full(K * columns, np.inf)
    for shift in (0, -1, 1):  # a cell's own points, then its neighbours' for an empty cell
        cell = ring[ok] * columns + (col[ok] + shift) % columns
        d = dist[ok]
        cand = np.full(K * columns, np.inf)
        np.minimum.at(cand, cell, d)
        best = np.where(np.isinf(best), cand, best) if shift else cand
    keep = np.flatnonzero(np.isfinite(best))
    k, c = keep // columns, keep % columns
    e, a, r = elev[k], c * step, best[keep]
    return np.stack([r * np.cos(e) * np.cos(a), r * np.cos(e) * np.sin(a), r * np.sin(e)], axis=1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("source")
    ap.add_argument("out")
    ap.add_argument("--speed", type=float, default=0.3, help="metres a sweep along x")
    ap.add_argument("--step", type=float, default=0.2, help="degrees a column")
    a = ap.parse_args()
    take, names, offsets, xyz = read_sweeps(a.source)
    rings = [n for n in ("ring", "channel", "laser_id") if n in take.attributes]
    if not rings:
        raise SystemExit(f"{a.source}: no ring field to find the lasers' elevations by")
    ring = np.asarray(take.attributes[rings[0]]).reshape(-1).astype(np.int64)
    good = np.isfinite(xyz).all(axis=1)
    elev = ring_elevations(xyz[good], ring[good])
    elev = elev[~np.isnan(elev)]  # the ring numbers the field never holds
    step = np.radians(a.step)
    columns = int(round(2 * np.pi / step))
    os.makedirs(a.out, exist_ok=True)
    for f, name in enumerate(names):
        sel = slice(offsets[f], offsets[f + 1])
        p = xyz[sel][good[sel]] - np.array([a.speed * f, 0.0, 0.0])
        write_xyz(os.path.join(a.out, name), render(p, elev, step, columns))
    print(f"{a.out}: {len(names)} sweeps, {a.speed} m a sweep along x")


if __name__ == "__main__":
    main()

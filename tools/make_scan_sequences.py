#!/usr/bin/env python3
"""Scan-like PCD sequences with point fields, for the tests and benchmarks of issue #15.

  make_scan_sequences.py depth MESH_DIR OUT_DIR [--frames N] [--width W --height H] [--seed S]
                           [--world]
  make_scan_sequences.py lidar OUT_DIR [--frames N] [--rings R] [--steps A] [--seed S]
                        [--order ring|azimuth] [--drive D] [--turn DEG] [--street] [--reflectivity]

depth: renders a mesh animation given as a folder of PCD frames (x y z, the same vertices in
  every frame, e.g. ../shared/data/pcd/horse-gallop) from a fixed virtual depth camera. Each
  frame is an organized W x H cloud in camera coordinates (metres-like units of the mesh):
  every vertex is projected (pinhole, 40 degree horizontal field of view, the camera looking at
  the first frame's centre from 1.5 bounding radii away) and splatted on a 2 x 2 pixel block
  with a z-buffer; pixels no vertex reaches are the NaN background (with --world the points are
  moved back into the mesh's coordinates, as a registered sequence has them). Fields, binary:
    x y z          float32, the pixel's surface point, depth with Gaussian noise (sigma 0.2 %
                   of the depth, as structured-light sensors have);
    rgb            packed float (PCL's spelling): a procedural texture of the vertex's rest
                   position (stripes), alpha 255;
    intensity      float32, 1 / depth^2 scaled, with 1 % noise;
    normal_x/y/z   float32, from the depth image (cross product of the neighbours' points;
                   NaN where a neighbour is background);
    label          uint16, the vertex's part (vertex index / 256; 0 for background).
lidar: a spinning-LiDAR-like sequence, unorganized: R rings (elevations -15..+15 degrees) x A
  azimuth steps per sweep; the scene is a ground plane, a ring of pillars and a sphere that
  moves; a beam that hits nothing within 60 units is a NaN point. Fields, binary:
    x y z       float32, with 1 cm range noise;
    intensity   float32, by surface (ground 0.2, pillars 0.6, sphere 0.9) over range, noisy;
    ring        uint16, the beam's ring;
    time        float32, seconds since the sweep began (10 Hz);
    reflectivity  uint8, with --reflectivity: the surface's reflectivity, textured in world
                coordinates (ground: asphalt patches of 2 x 2 units and painted stripes across
                x; each pillar its own; the sphere bright), +-1 noise, 0 where nothing is hit.
  --order azimuth stores the points column by column (every ring at one azimuth, then the next
  azimuth, as Velodyne and Ouster packets give them) instead of ring by ring; --drive D moves
  the sensor D units along x per frame (a vehicle's scan: the points stay in sensor
  coordinates, the scene slides by), so a beam sees other surface points in every frame; --turn
  DEG turns the sensor DEG degrees about its z axis per frame (a turning platform: the scene
  turns the other way in sensor coordinates); --street adds two walls 6 units high along x, 8
  units either side of the sensor's path (a street: most beams above the ground hit a wall).
  Without these options the output is what it was before they existed.
Point p is the same pixel (depth) or beam (lidar) in every frame, as capz needs.
"""
import argparse
import math
import os
import struct
import sys

import numpy as np


def read_pcd_xyz(path):
    with open(path, "rb") as f:
        data = f.read()
    fields, sizes, types, counts, n, kind, off = None, None, None, None, 0, None, 0
    pos = 0
    while True:
        e = data.index(b"\n", pos)
        line = data[pos:e].decode("ascii").split()
        pos = e + 1
        if not line or line[0].startswith("#"):
            continue
        k = line[0]
        if k == "FIELDS":
            fields = line[1:]
        elif k == "SIZE":
            sizes = [int(x) for x in line[1:]]
        elif k == "TYPE":
            types = line[1:]
        elif k == "COUNT":
            counts = [int(x) for x in line[1:]]
        elif k == "POINTS":
            n = int(line[1])
        elif k == "DATA":
            kind = line[1]
            off = pos
            break
    counts = counts or [1] * len(fields)
    if kind == "ascii":
        vals = np.loadtxt(data[off:].decode("ascii").splitlines(), dtype=np.float64, ndmin=2)
        cols = []
        c = 0
        for name, cnt in zip(fields, counts):
            if name in ("x", "y", "z"):
                cols.append(vals[:, c])
            c += cnt
        return np.stack(cols, axis=1)
    if kind != "binary":
        raise SystemExit(f"{path}: only ascii and binary PCD sources are read here")
    dt = []
    for name, s, t, cnt in zip(fields, sizes, types, counts):
        base = {"F": "f", "U": "u", "I": "i"}[t] + str(s)
        dt.append((name if name != "_" else f"_{len(dt)}", "<" + base, (cnt,) if cnt > 1 else ()))
    arr = np.frombuffer(data, dtype=np.dtype(dt), count=n, offset=off)
    return np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(np.float64)


def write_pcd(path, width, height, fields, arrays):
    """fields: list of (name, type, size, count); arrays: matching numpy arrays (n[, count])."""
    n = width * height
    dt = []
    for (name, t, s, c) in fields:
        base = {"F": "f", "U": "u", "I": "i"}[t] + str(s)
        dt.append((name, "<" + base, (c,) if c > 1 else ()))
    rec = np.zeros(n, dtype=np.dtype(dt))
    for (name, _, _, _), a in zip(fields, arrays):
        rec[name] = a
    head = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\n"
    head += "FIELDS " + " ".join(f[0] for f in fields) + "\n"
    head += "SIZE " + " ".join(str(f[2]) for f in fields) + "\n"
    head += "TYPE " + " ".join(f[1] for f in fields) + "\n"
    head += "COUNT " + " ".join(str(f[3]) for f in fields) + "\n"
    head += f"WIDTH {width}\nHEIGHT {height}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA binary\n"
    with open(path, "wb") as f:
        f.write(head.encode("ascii"))
        f.write(rec.tobytes())


def pack_rgb(r, g, b):
    u = (np.uint32(255) << 24) | (r.astype(np.uint32) << 16) | (g.astype(np.uint32) << 8) | b.astype(np.uint32)
    return u.view(np.float32)


def depth(args):
    names = sorted((f for f in os.listdir(args.mesh) if f.endswith(".pcd")),
                   key=lambda s: [int(t) if t.isdigit() else t for t in __import__("re").split(r"(\d+)", s)])
    names = names[: args.frames]
    rng = np.random.default_rng(args.seed)
    W, H = args.width, args.height
    rest = read_pcd_xyz(os.path.join(args.mesh, names[0]))
    centre = rest.mean(axis=0)
    radius = np.linalg.norm(rest - centre, axis=1).max()
    cam = centre + np.array([0.0, 0.0, 1.5 * radius])  # looking down -z at the centre
    f_px = (W / 2) / math.tan(math.radians(20))
    # Texture: stripes of the rest position.
    tr = (128 + 127 * np.sin(rest[:, 0] / radius * 9)).astype(np.uint8)
    tg = (128 + 127 * np.sin(rest[:, 1] / radius * 7 + 1)).astype(np.uint8)
    tb = (128 + 127 * np.sin(rest[:, 2] / radius * 5 + 2)).astype(np.uint8)
    part = (np.arange(len(rest)) // 256 + 1).astype(np.uint16)
    os.makedirs(args.out, exist_ok=True)
    for fi, name in enumerate(names):
        v = read_pcd_xyz(os.path.join(args.mesh, name)) - cam
        z = -v[:, 2]
        ok = z > 1e-6
        u = np.where(ok, W / 2 + f_px * v[:, 0] / np.where(ok, z, 1), -1)
        w = np.where(ok, H / 2 - f_px * v[:, 1] / np.where(ok, z, 1), -1)
        zbuf = np.full(W * H, np.inf)
        owner = np.full(W * H, -1, dtype=np.int64)
        order = np.argsort(-z)  # far first, near overwrite
        for dx in (0, 1):
            for dy in (0, 1):
                px = np.floor(u[order]).astype(np.int64) + dx
                py = np.floor(w[order]).astype(np.int64) + dy
                inside = ok[order] & (px >= 0) & (px < W) & (py >= 0) & (py < H)
                idx = py[inside] * W + px[inside]
                src = order[inside]
                closer = z[src] < zbuf[idx]
                zbuf[idx[closer]] = z[src[closer]]
                owner[idx[closer]] = src[closer]
        hit = owner >= 0
        d = np.where(hit, zbuf, np.nan)
        d = d * (1 + rng.normal(0, 0.002, W * H))
        pxs = np.arange(W * H) % W
        pys = np.arange(W * H) // W
        X = (pxs + 0.5 - W / 2) / f_px * d
        Y = -(pys + 0.5 - H / 2) / f_px * d
        Z = -d
        # --world: the points in the mesh's coordinates (a registered sequence), so they move
        # along rays from the camera, not from the origin.
        P = (np.stack([X, Y, Z], axis=1) + (cam if args.world else 0.0)).astype(np.float32)
        img = P.reshape(H, W, 3).astype(np.float64)
        dxv = np.full_like(img, np.nan)
        dyv = np.full_like(img, np.nan)
        dxv[:, :-1] = img[:, 1:] - img[:, :-1]
        dyv[:-1, :] = img[1:, :] - img[:-1, :]
        nrm = np.cross(dxv, dyv)
        nrm /= np.linalg.norm(nrm, axis=2, keepdims=True)
        nrm = nrm.reshape(-1, 3).astype(np.float32)
        o = np.where(hit, owner, 0)
        rgb = np.where(hit, pack_rgb(tr[o], tg[o], tb[o]), np.float32(np.nan))
        inten = np.where(hit, 1.0 / (d * d) * radius * radius * (1 + rng.normal(0, 0.01, W * H)), np.nan).astype(np.float32)
        label = np.where(hit, part[o], 0).astype(np.uint16)
        fields = [("x", "F", 4, 1), ("y", "F", 4, 1), ("z", "F", 4, 1), ("rgb", "F", 4, 1),
                  ("intensity", "F", 4, 1), ("normal_x", "F", 4, 1), ("normal_y", "F", 4, 1),
                  ("normal_z", "F", 4, 1), ("label", "U", 2, 1)]
        arrays = [P[:, 0], P[:, 1], P[:, 2], rgb, inten, nrm[:, 0], nrm[:, 1], nrm[:, 2], label]
        write_pcd(os.path.join(args.out, f"frame_{fi:05d}.pcd"), W, H, fields, arrays)


def lidar(args):
    rng = np.random.default_rng(args.seed)
    R, A = args.rings, args.steps
    elev = np.radians(np.linspace(-15, 15, R))
    az = np.linspace(0, 2 * math.pi, A, endpoint=False)
    azimuth_major = args.order == "azimuth"
    E, AZ = np.meshgrid(elev, az, indexing="xy" if azimuth_major else "ij")
    dirs = np.stack([np.cos(E) * np.cos(AZ), np.cos(E) * np.sin(AZ), np.sin(E)], axis=-1).reshape(-1, 3)
    if azimuth_major:
        ring = np.tile(np.arange(R, dtype=np.uint16), A)
        t_in_sweep = (np.repeat(np.arange(A), R) / A * 0.1).astype(np.float32)
    else:
        ring = np.repeat(np.arange(R, dtype=np.uint16), A)
        t_in_sweep = (np.tile(np.arange(A), R) / A * 0.1).astype(np.float32)
    pillars = [(12 * math.cos(k * 2 * math.pi / 9), 12 * math.sin(k * 2 * math.pi / 9)) for k in range(9)]
    os.makedirs(args.out, exist_ok=True)
    for fi in range(args.frames):
        ox = args.drive * fi  # the sensor's x in the world
        # The sensor's yaw in the world (--turn): the rays are cast along the directions turned.
        yaw = math.radians(args.turn * fi)
        cw, sw = math.cos(yaw), math.sin(yaw)
        sensor_dirs = dirs
        dirs = np.stack([cw * sensor_dirs[:, 0] - sw * sensor_dirs[:, 1],
                         sw * sensor_dirs[:, 0] + cw * sensor_dirs[:, 1], sensor_dirs[:, 2]], axis=-1)
        rng_t = np.full(len(dirs), np.inf)
        kind = np.zeros(len(dirs))
        which = np.full(len(dirs), -1)  # the pillar hit
        # Ground z = -1.7.
        tz = np.where(dirs[:, 2] < -1e-6, -1.7 / np.where(dirs[:, 2] < -1e-6, dirs[:, 2], -1), np.inf)
        better = tz < rng_t
        rng_t[better], kind[better] = tz[better], 0.2
        # Pillars: vertical cylinders of radius 0.4.
        dx, dy = dirs[:, 0], dirs[:, 1]
        a = dx * dx + dy * dy
        for k, (cx, cy) in enumerate(pillars):
            cx = cx - ox
            b = -2 * (dx * cx + dy * cy)
            c = cx * cx + cy * cy - 0.16
            disc = b * b - 4 * a * c
            t = np.where(disc >= 0, (-b - np.sqrt(np.maximum(disc, 0))) / (2 * np.maximum(a, 1e-12)), np.inf)
            t = np.where(t > 0, t, np.inf)
            better = t < rng_t
            rng_t[better], kind[better] = t[better], 0.6
            which[better] = k
        if args.street:  # two walls along x, 8 units either side, 6 high, the street between
            for wy in (-8.0, 8.0):
                t = np.where(np.abs(dy) > 1e-9, wy / np.where(np.abs(dy) > 1e-9, dy, 1), np.inf)
                hz = t * dirs[:, 2]
                t = np.where((t > 0) & (hz > -1.7) & (hz < 4.3), t, np.inf)
                better = t < rng_t
                rng_t[better], kind[better] = t[better], 0.4
        # A sphere of radius 1 moving along a circle.
        s = np.array([6 * math.cos(fi * 0.05) - ox, 6 * math.sin(fi * 0.05), -0.5])
        b = -2 * dirs @ s
        c = s @ s - 1.0
        disc = b * b - 4 * c
        t = np.where(disc >= 0, (-b - np.sqrt(np.maximum(disc, 0))) / 2, np.inf)
        t = np.where(t > 0, t, np.inf)
        better = t < rng_t
        rng_t[better], kind[better] = t[better], 0.9
        hit = rng_t < 60
        rr = np.where(hit, rng_t + rng.normal(0, 0.01, len(dirs)), np.nan)
        dirs = sensor_dirs  # the points in the sensor's frame
        P = (dirs * rr[:, None]).astype(np.float32)
        inten = np.where(hit, kind / np.maximum(rr, 1) * 10 * (1 + rng.normal(0, 0.03, len(dirs))), np.nan).astype(np.float32)
        time = (t_in_sweep + np.float32(0.1 * fi)).astype(np.float32)
        fields = [("x", "F", 4, 1), ("y", "F", 4, 1), ("z", "F", 4, 1), ("intensity", "F", 4, 1),
                  ("ring", "U", 2, 1), ("time", "F", 4, 1)]
        arrays = [P[:, 0], P[:, 1], P[:, 2], inten, ring, time]
        if args.reflectivity:
            wx, wy = P[:, 0].astype(np.float64) + ox, P[:, 1].astype(np.float64)
            patch = 25 + 3 * ((np.floor(wx / 2) * 7 + np.floor(wy / 2) * 13) % 5)
            stripe = (np.abs(wy) < 4) & ((wx % 6) < 0.5)
            refl = np.where(kind == 0.2, np.where(stripe, 180, patch),
                            np.where(kind == 0.6, 90 + 12 * which, 230))
            refl = refl + rng.integers(-1, 2, len(dirs))
            refl = np.where(hit, np.clip(refl, 1, 255), 0).astype(np.uint8)
            fields.append(("reflectivity", "U", 1, 1))
            arrays.append(refl)
        write_pcd(os.path.join(args.out, f"sweep_{fi:05d}.pcd"), len(dirs), 1, fields, arrays)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    d = sub.add_parser("depth")
    d.add_argument("mesh")
    d.add_argument("out")
    d.add_argument("--frames", type=int, default=40)
    d.add_argument("--width", type=int, default=160)
    d.add_argument("--height", type=int, default=120)
    d.add_argument("--seed", type=int, default=1)
    d.add_argument("--world", action="store_true",
                   help="points in the mesh's coordinates, not the camera's")
    l = sub.add_parser("lidar")
    l.add_argument("out")
    l.add_argument("--frames", type=int, default=40)
    l.add_argument("--rings", type=int, default=16)
    l.add_argument("--steps", type=int, default=720)
    l.add_argument("--seed", type=int, default=1)
    l.add_argument("--order", choices=("ring", "azimuth"), default="ring")
    l.add_argument("--drive", type=float, default=0.0)
    l.add_argument("--turn", type=float, default=0.0)
    l.add_argument("--street", action="store_true")
    l.add_argument("--reflectivity", action="store_true")
    a = ap.parse_args()
    np.seterr(invalid="ignore", divide="ignore")
    depth(a) if a.cmd == "depth" else lidar(a)


if __name__ == "__main__":
    sys.exit(main())

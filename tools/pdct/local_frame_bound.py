#!/usr/bin/python3
"""Upper bound on what pdct's local-frame prediction can add to the position coder on mocap takes.

usage: tools/pdct/local_frame_bound.py RAWDUMP STEP TAKE [TAKE ...]
  RAWDUMP  path of build/tools/capz_rawdump (writes the take's positions as float32 + mask)
  STEP     grid step in the take's units (2 x the max error: 0.2 = 0.1 mm, 2 = 1 mm)

Needs numpy (Debian: python3-numpy, for /usr/bin/python3).

Every marker is quantised to the grid. For each marker i >= 3 with at least 50 frames where it
and its six nearest earlier markers (by mean position, index < i: what a decoder has already
decoded in the frame) are valid at t, t-1 and t-2, the script measures the zeroth-order empirical
entropy (bits per coordinate) of the integer residuals of six predictors:
  L1  q(t-1)                        L2  2 q(t-1) - q(t-2)
  R1  L1 + (q_r(t) - q_r(t-1))      R2  L2 + (q_r(t) - 2 q_r(t-1) + q_r(t-2))   best r of the six
  F1  local frame (pdct's: origin at the a-b midpoint, x along a-b, y in the triangle's plane)
      of three earlier markers a, b, c: the marker's local coordinates at t-1 mapped by the frame
      at t, rounded to the grid                                               best triangle
  F2  the same with the local coordinates extrapolated linearly from t-1 and t-2.
L1/L2/R1/R2 are what the format-2 bound coder already chooses between (FORMAT.md 8); F1/F2 are
pdct's idea. Each marker takes its best predictor for the whole take, chosen by an oracle and
with no side cost, so 'gain' = 1 - best(all) / best(L1, L2, R1, R2) bounds from above what adding
local-frame predictors to the coder could save on the position residuals.
"""
import itertools
import json
import os
import subprocess
import sys
import tempfile

import numpy as np


def entropy(r):
    _, c = np.unique(r.astype(np.int64).ravel(), return_counts=True)
    p = c / c.sum()
    return float(-(p * np.log2(p)).sum())


def local_frame(a, b, c):
    o = (a + b) / 2
    x = b - a
    x /= np.linalg.norm(x, axis=1, keepdims=True) + 1e-12
    w = c - o
    y = w - (w * x).sum(1, keepdims=True) * x
    y /= np.linalg.norm(y, axis=1, keepdims=True) + 1e-12
    return o, np.stack([x, y, np.cross(x, y)], axis=2)  # columns x, y, z


def bound(path, rawdump, step):
    with tempfile.TemporaryDirectory() as tmp:
        f32, mask, meta = (os.path.join(tmp, n) for n in ("p.f32", "p.mask", "p.json"))
        subprocess.run([rawdump, path, f32, "--mask", mask, "--meta", meta], check=True,
                       stdout=subprocess.DEVNULL)
        m = json.load(open(meta))
        F, N = m["frames"], m["points"]
        X = np.fromfile(f32, dtype="<f4").reshape(F, N, 3).astype(np.float64)
        V = np.fromfile(mask, dtype=np.uint8).reshape(F, N) != 0
    Q = np.round(X / step)
    mean = np.array([X[V[:, i], i].mean(0) if V[:, i].any() else np.zeros(3) for i in range(N)])
    names = ["L1", "L2", "R1", "R2", "F1", "F2"]
    total = dict.fromkeys(names + ["best_LR", "best_all"], 0.0)
    coords = 0
    t = np.arange(2, F)
    for i in range(3, N):
        ok = V[t, i] & V[t - 1, i] & V[t - 2, i]
        near = np.argsort(np.linalg.norm(mean[:i] - mean[i], axis=1))[:6]
        for r in near:
            ok &= V[t, r] & V[t - 1, r] & V[t - 2, r]
        tt = t[ok]
        if len(near) < 3 or len(tt) < 50:
            continue
        q = Q[:, i]
        d1 = q[tt] - q[tt - 1]
        d2 = q[tt] - 2 * q[tt - 1] + q[tt - 2]
        e = {"L1": entropy(d1), "L2": entropy(d2),
             "R1": min(entropy(d1 - (Q[tt, r] - Q[tt - 1, r])) for r in near),
             "R2": min(entropy(d2 - (Q[tt, r] - 2 * Q[tt - 1, r] + Q[tt - 2, r])) for r in near),
             "F1": np.inf, "F2": np.inf}
        for a, b, c in itertools.permutations(near[:5], 3):
            if a > b:  # the frame's x axis only flips sign: the same predictor
                continue
            fr = [local_frame(Q[tt - k, a] * step, Q[tt - k, b] * step, Q[tt - k, c] * step)
                  for k in range(3)]
            loc = [np.einsum("tji,tj->ti", fr[k][1], q[tt - k] * step - fr[k][0]) for k in (1, 2)]
            o0, r0 = fr[0]
            p1 = o0 + np.einsum("tij,tj->ti", r0, loc[0])
            p2 = o0 + np.einsum("tij,tj->ti", r0, 2 * loc[0] - loc[1])
            e["F1"] = min(e["F1"], entropy(q[tt] - np.round(p1 / step)))
            e["F2"] = min(e["F2"], entropy(q[tt] - np.round(p2 / step)))
        n = 3 * len(tt)
        for k in names:
            total[k] += e[k] * n
        total["best_LR"] += min(e[k] for k in ["L1", "L2", "R1", "R2"]) * n
        total["best_all"] += min(e.values()) * n
        coords += n
    return coords, {k: v / coords for k, v in total.items()} if coords else {}


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    rawdump, step = sys.argv[1], float(sys.argv[2])
    print("| take | step | coordinates | L1 | L2 | R1 | R2 | F1 | F2 | best of L/R | best of all | gain |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for path in sys.argv[3:]:
        n, b = bound(path, rawdump, step)
        if not n:
            print(f"| {os.path.basename(path)} | {step:g} | 0 | (no marker qualifies) |")
            continue
        cols = " | ".join(f"{b[k]:.3f}" for k in ["L1", "L2", "R1", "R2", "F1", "F2", "best_LR", "best_all"])
        print(f"| {os.path.basename(path)} | {step:g} | {n} | {cols} | "
              f"{100 * (1 - b['best_all'] / b['best_LR']):.1f} % |")


if __name__ == "__main__":
    main()

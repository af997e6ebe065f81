#!/usr/bin/python3
"""ts codec measurements recorded in docs/BENCHMARKS.md (ts section).

Usage (repository root, after a Release build in build/):
  python3 tools/ts_bench.py [--out bench-out/ts] [--quick]

1. The paper's Table 2 (Luo et al. 2013): clusters 1..5 at a fixed KG error on horse-gallop and
   chickenCrossing (build/tools/capz_tsbench table2), with the encoder's time per step (Table 3).
2. Rate-distortion, bpvf against KG error 0.02 % .. 1 %, on horse-gallop, chickenCrossing, pcow:
   ts (--clusters auto) against the simple quantise + linear-predict + `xz -9e` reference coder
   (build/tools/capz_refcoder, the bench harness's "refcoder"): its tolerance T is searched so its
   KG error lands at or just under the target (KG measured by build/tools/capz_metrics), and
   against `capz compress --kg-error` through the container without a transform (the bound-layer
   coder: its grid meets the target) and with `--codec ts` (a transform-output stream: ts's
   reconstruction is the output, FORMAT.md 4.3; whole .capz file).
Everything is printed as markdown tables (and written to OUT/ts_bench.md).
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BUILD = os.path.join(ROOT, "build")
DATA = os.path.join(ROOT, "..", "shared", "data", "pcd")
TSBENCH = os.path.join(BUILD, "tools", "capz_tsbench")
REFCODER = os.path.join(BUILD, "tools", "capz_refcoder")
METRICS = os.path.join(BUILD, "tools", "capz_metrics")
CLI = os.path.join(BUILD, "capz")

SHAPES = {"horse-gallop": (48, 8431), "chickenCrossing": (400, 3030), "pcow": (204, 2904),
          "AlbertoREAL.c3d": (4921, 64), "FunctionalLHip.c3d": (1577, 74)}
C3D = os.path.join(ROOT, "..", "shared", "data", "c3d")
PATHS = {"AlbertoREAL.c3d": os.path.join(C3D, "c3dorg", "sample_34", "AlbertoREAL.c3d"),
         "FunctionalLHip.c3d": os.path.join(C3D, "btkdata", "others", "FunctionalLHip.c3d")}


def src_of(seq):
    """A PCD sequence name (a folder of ../shared/data/pcd) or one of the C3D takes of PATHS."""
    return PATHS.get(seq, os.path.join(DATA, seq))


def run(cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


def refcoder_kg(seq, tol, tmp):
    src = src_of(seq)
    binf = os.path.join(tmp, "ref.bin")
    run([REFCODER, "encode", src, binf, "--tolerance", repr(tol)])
    f32 = os.path.join(tmp, "ref.f32")
    run([REFCODER, "decode", binf, f32])
    return json.loads(run([METRICS, src, f32]))["kg_error"]


def refcoder_at_kg(seq, kg, tmp):
    """Largest tolerance whose KG error is <= kg (bisection in log space); xz -9e size at it."""
    lo, hi = 1e-7, 1.0
    best = None
    for _ in range(40):
        mid = math.sqrt(lo * hi)
        got = refcoder_kg(seq, mid, tmp)
        if got <= kg:
            lo, best = mid, (got, mid)
        else:
            hi = mid
        if best and hi / lo < 1.02:
            break
    run([REFCODER, "encode", src_of(seq), os.path.join(tmp, "ref.bin"), "--tolerance", repr(best[1])])
    xz = subprocess.run(["xz", "-9e", "-c", os.path.join(tmp, "ref.bin")], check=True, capture_output=True).stdout
    return len(xz), best[0], best[1]


def cli_at_kg(seq, kg, tmp, codec):
    """capz compress through the container (its grid meets the KG target), bytes of the .capz."""
    out = os.path.join(tmp, "c.capz")
    r = subprocess.run([CLI, "compress", src_of(seq), "-o", out, "-f", "-q", "--kg-error", str(kg),
                        "--codec", codec], capture_output=True, text=True)
    if r.returncode != 0:
        return None
    return os.path.getsize(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(ROOT, "bench-out", "ts"))
    ap.add_argument("--quick", action="store_true", help="fewer KG targets")
    ap.add_argument("--seqs", default="horse-gallop,chickenCrossing,pcow", help="RD sequences")
    ap.add_argument("--kgs", default="", help="RD KG targets, comma-separated")
    ap.add_argument("--no-table2", action="store_true")
    ap.add_argument("--no-rd", action="store_true")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    lines = []

    def emit(s=""):
        print(s, flush=True)
        lines.append(s)

    if a.no_table2:
        table2 = ()
    else:
        table2 = ("horse-gallop", "chickenCrossing")
    emit("## Table 2 (clusters 1..5 at KG 0.15 %), default options")
    for seq in table2:
        emit(run([TSBENCH, "table2", src_of(seq), "--kg", "0.15"]))
    emit("## Table 2, the paper's own settings (basis bits 8..16, no basis prediction, one segment)")
    for seq in table2:
        emit(run([TSBENCH, "table2", src_of(seq), "--kg", "0.15", "--opt", "basis_bits_min=8",
                  "--opt", "basis_bits_max=16", "--opt", "basis_predict=0", "--opt", "basis_free_step=0", "--opt", "segments=1"]))

    kgs = [0.05, 0.15, 0.5] if a.quick else [0.02, 0.05, 0.1, 0.15, 0.25, 0.5, 1.0]
    if a.kgs:
        kgs = [float(x) for x in a.kgs.split(",")]
    emit("## Rate-distortion: ts (clusters auto) against the reference coder (quantise + predict + xz -9e)")
    with tempfile.TemporaryDirectory() as tmp:
        for seq in ([] if a.no_rd else a.seqs.split(",")):
            f, n = SHAPES[seq]
            ts_rows = run([TSBENCH, "rd", src_of(seq), "--kg", ",".join(map(str, kgs)),
                           "--clusters", "auto"]).strip().splitlines()
            emit(f"### {seq} ({f} frames x {n} points)")
            emit("| KG target (%) | ts K {PCs} | ts KG (%) | ts bytes | ts bpvf | ref KG (%) | ref bytes | ref bpvf | ref / ts "
                 "| capz (no transform) bpvf | capz --codec ts bpvf | ref / capz --codec ts |")
            emit("|---|---|---|---|---|---|---|---|---|---|---|---|")
            for kg, row in zip(kgs, ts_rows[3:]):
                c = [x.strip() for x in row.strip("|").split("|")]
                ts_bytes = int(c[4])
                ref = refcoder_at_kg(seq, kg, tmp)
                plain = cli_at_kg(seq, kg, tmp, "none")
                via = cli_at_kg(seq, kg, tmp, "ts")
                ref_bpvf = 8.0 * ref[0] / (f * n)
                fmt = lambda b: f"{8.0 * b / (f * n):.3f}" if b else "n/a"
                emit(f"| {kg} | {c[1]} | {c[2]} | {ts_bytes} | {c[5]} | {ref[1]:.4f} | {ref[0]} | {ref_bpvf:.3f} | "
                     f"{ref[0] / ts_bytes:.2f} | {fmt(plain)} | {fmt(via)} | "
                     f"{(ref[0] / via) if via else 0:.2f} |")
    with open(os.path.join(a.out, "ts_bench.md"), "w") as fh:
        fh.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main())

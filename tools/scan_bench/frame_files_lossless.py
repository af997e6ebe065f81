#!/usr/bin/env python3
"""PLY, KITTI .bin and nuScenes .pcd.bin frame folders made from the shared scan sequences, compressed with
`capz compress --lossless`, given back by `capz decompress` and compared byte for byte (`cmp` of
every frame file), with the archive's size against `xz -9e` of the frame files (one tar of the
folder in name order, as BENCHMARKS "Scan folders with --lossless" measures PCD folders).

Variants of each sequence (docs/FORMAT.md "Lossless frame-file streams"):
  ply-le      capz convert --to ply --ply-encoding binary_little_endian (every field)
  ply-be      the same, binary_big_endian
  ply-ascii   the same, ascii (capz's number spelling)
  ply-f6      a Python writer's ascii PLY: comment line, float x y z intensity, "%.6f" numbers,
              an empty face element (as Open3D-era exporters write)
  ply-f6d     the same with double properties (the positions on a decimal grid of 6 digits)
  bin         a Python writer's KITTI .bin: float32 x y z intensity (array.tofile, the bytes
              numpy's tofile gives)
  nus         the same in nuScenes' layout and names: NAME.pcd.bin, float32 x y z intensity ring
              (the ring the source's ring or channel field, 0 without one)

usage: frame_files_lossless.py CAPZ SCAN_DIR WORK_DIR [SEQUENCE ...] [--variants a,b]
Prints one Markdown row per sequence and variant.
"""
import array
import os
import subprocess
import sys


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, **kw)


def read_ascii_pcd(path):
    """(field names, rows of text tokens) of an ascii PCD frame."""
    with open(path) as f:
        fields = []
        for line in f:
            w = line.split()
            if w and w[0] == "FIELDS":
                fields = w[1:]
            if w and w[0] == "DATA":
                break
        return fields, [line.split() for line in f if line.strip()]


def write_python_ply(path, fields, rows, double):
    """ascii PLY of x y z intensity in "%.6f" (NaN points written as nan)."""
    cols = [fields.index(n) for n in ("x", "y", "z")]
    cols.append(fields.index("intensity") if "intensity" in fields else -1)
    t = "double" if double else "float"
    head = ["ply", "format ascii 1.0", "comment written by a Python script",
            "element vertex %d" % len(rows)]
    head += ["property %s %s" % (t, n) for n in ("x", "y", "z", "intensity")]
    head += ["element face 0", "property list uchar int vertex_indices", "end_header"]
    out = ["\n".join(head) + "\n"]
    for r in rows:
        vals = [float(r[c]) if c >= 0 else 0.0 for c in cols]
        out.append(" ".join("%.6f" % v for v in vals) + "\n")
    with open(path, "w") as f:
        f.write("".join(out))


def write_python_bin(path, fields, rows, ring=False):
    cols = [fields.index(n) for n in ("x", "y", "z")]
    cols.append(fields.index("intensity") if "intensity" in fields else -1)
    if ring:
        names = [n for n in ("ring", "channel") if n in fields]
        cols.append(fields.index(names[0]) if names else -1)
    a = array.array("f")
    for r in rows:
        a.extend(float(r[c]) if c >= 0 else 0.0 for c in cols)
    if sys.byteorder != "little":
        a.byteswap()
    with open(path, "wb") as f:
        a.tofile(f)


def make_variant(capz, src, ascii_dir, out, variant):
    os.makedirs(out, exist_ok=True)
    if variant in ("ply-le", "ply-be", "ply-ascii"):
        enc = {"ply-le": "binary_little_endian", "ply-be": "binary_big_endian",
               "ply-ascii": "ascii"}[variant]
        run([capz, "convert", src, out + "/", "--to", "ply", "--ply-encoding", enc, "-f", "-q"])
        return
    for name in sorted(os.listdir(ascii_dir)):
        fields, rows = read_ascii_pcd(os.path.join(ascii_dir, name))
        stem = os.path.splitext(name)[0]
        if variant == "bin":
            write_python_bin(os.path.join(out, stem + ".bin"), fields, rows)
        elif variant == "nus":
            write_python_bin(os.path.join(out, stem + ".pcd.bin"), fields, rows, ring=True)
        else:
            write_python_ply(os.path.join(out, stem + ".ply"), fields, rows, variant == "ply-f6d")


def xz_tar(folder):
    names = sorted(os.listdir(folder))
    tar = subprocess.Popen(["tar", "cf", "-", "--sort=name"] + names, cwd=folder,
                           stdout=subprocess.PIPE)
    xz = subprocess.run(["xz", "-9e", "-T1"], stdin=tar.stdout, capture_output=True, check=True)
    tar.wait()
    return len(xz.stdout)


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--variants")]
    variants = ["ply-le", "ply-be", "ply-ascii", "ply-f6", "ply-f6d", "bin"]
    for a in sys.argv[1:]:
        if a.startswith("--variants="):
            variants = a.split("=", 1)[1].split(",")
    if len(args) < 3:
        sys.exit(__doc__)
    capz, scans, work = os.path.abspath(args[0]), args[1], args[2]
    seqs = args[3:] or ["robosense-helios16p", "robosense-e1", "pandar64-factory20"]
    print("| sequence | variant | frame files (B) | capz --lossless (B) | xz -9e tar (B) "
          "| capz / xz | byte for byte |")
    print("|---|---|---:|---:|---:|---:|---|")
    for s in seqs:
        src = os.path.join(scans, s)
        ascii_dir = os.path.join(work, s + "-pcd-ascii")
        if not os.path.isdir(ascii_dir):
            run([capz, "convert", src, ascii_dir + "/", "--pcd-encoding", "ascii", "-f", "-q"])
        for v in variants:
            out = os.path.join(work, s + "-" + v)
            if not os.path.isdir(out):
                make_variant(capz, src, ascii_dir, out, v)
            z, back = out + ".capz", out + "-back"
            try:
                run([capz, "compress", out, "-o", z, "--lossless", "-f", "-q"])
            except subprocess.CalledProcessError as e:  # e.g. float64 on no grid: a row saying so
                print("| %s | %s | | refused: %s | | | |" % (s, v, e.stderr.strip()), flush=True)
                continue
            run(["rm", "-rf", back])
            run([capz, "decompress", z, "-o", back + "/", "-q"])
            names = sorted(os.listdir(out))
            same = sorted(os.listdir(back)) == names and all(
                subprocess.run(["cmp", "-s", os.path.join(out, n), os.path.join(back, n)])
                .returncode == 0 for n in names)
            size = sum(os.path.getsize(os.path.join(out, n)) for n in names)
            zx = xz_tar(out)
            print("| %s | %s | %s | %s | %s | %.2f | %s |" % (
                s, v, f"{size:,}", f"{os.path.getsize(z):,}", f"{zx:,}",
                os.path.getsize(z) / zx, "yes (%d files)" % len(names) if same else "NO"),
                flush=True)


if __name__ == "__main__":
    main()

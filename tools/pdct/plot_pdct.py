#!/usr/bin/python3
"""Plots of the pdct experiments (docs/BENCHMARKS.md, "pdct") from pdct_bench CSV output.

  plot_pdct.py OUTDIR grid_SEQ.csv... kg_SEQ.csv...

grid CSVs give the paper's Figure 4 (KG error and bpvf against the share of zeroed DCT
coefficients, one line per cluster count and coefficient bits); kg CSVs give Figure 6 (rate
against KG error, one curve per cluster count). One PNG per sequence and figure."""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def figure4(out, take, data):
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.2))
    lines = defaultdict(list)
    for r in data:
        lines[(int(r["clusters"]), int(r["coef_bits"]))].append(r)
    styles = {8: ":", 10: "--", 12: "-"}
    for (n, bits), rs in sorted(lines.items()):
        rs.sort(key=lambda r: float(r["zero_share"]))
        z = [100 * float(r["zero_share"]) for r in rs]
        label = f"{n} clusters, {bits} bits"
        a.plot(z, [float(r["kg"]) for r in rs], styles.get(bits, "-"), marker="o", ms=3, label=label)
        b.plot(z, [float(r["bpvf"]) for r in rs], styles.get(bits, "-"), marker="o", ms=3, label=label)
    a.set_xlabel("zeroed DCT coefficients (%)")
    a.set_ylabel("KG error (%)")
    a.set_yscale("log")
    b.set_xlabel("zeroed DCT coefficients (%)")
    b.set_ylabel("bpvf (transform payload)")
    a.set_title(f"{take}: distortion")
    b.set_title(f"{take}: rate")
    b.legend(fontsize=7, ncol=1)
    for ax in (a, b):
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    p = os.path.join(out, f"pdct_fig4_{take}.png")
    fig.savefig(p, dpi=110)
    print(p)


def figure6(out, take, data):
    fig, ax = plt.subplots(figsize=(6, 4.2))
    curves = defaultdict(list)
    for r in data:
        curves[r["clusters"]].append(r)
    for n, rs in sorted(curves.items(), key=lambda kv: int(kv[0]) if kv[0].lstrip("-").isdigit() else 999):
        rs.sort(key=lambda r: float(r["bpvf"]))
        ax.plot([float(r["bpvf"]) for r in rs], [float(r["kg"]) for r in rs], marker="o", ms=3,
                label=f"pdct, {n} clusters")
    ax.set_xlabel("bpvf (transform payload)")
    ax.set_ylabel("KG error (%)")
    ax.set_yscale("log")
    ax.set_title(f"{take}: rate-distortion")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    p = os.path.join(out, f"pdct_fig6_{take}.png")
    fig.savefig(p, dpi=110)
    print(p)


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    by = defaultdict(list)
    for path in sys.argv[2:]:
        for r in rows(path):
            by[(r["mode"], r["take"])].append(r)
    for (mode, take), data in sorted(by.items()):
        if mode == "grid":
            figure4(out, take, data)
        elif mode == "kg":
            figure6(out, take, data)
    return 0


if __name__ == "__main__":
    sys.exit(main())

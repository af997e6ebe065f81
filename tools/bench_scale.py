"""Scale benchmark (tools/bench --scale): encode/decode time and peak memory against take length.

A synthetic take is made from a real one by build/tools/capz_synth (frames played forwards and
backwards, 100 markers, 200 Hz, 0.05 mm Gaussian noise, the source's gap pattern kept) for each
length, written as a float C3D by capz's own writer, then compressed and decompressed with capz's
defaults. `capz info` on the same file gives the memory of reading the take alone, so the
encoder's own share can be told apart from the reader's.
"""

import csv
import os
import sys

SOURCE = "c3d/c3dorg/sample_37/ART-Human_2persons_integer.c3d"
FIELDS = ["minutes", "frames", "points", "input_bytes", "raw_f32_bytes", "capz_bytes", "bpvf",
          "read_wall_s", "read_peak_mb", "enc_wall_s", "enc_cpu_s", "enc_peak_mb", "dec_wall_s",
          "dec_cpu_s", "dec_peak_mb", "enc_mb_s", "dec_mb_s", "note"]


def run_scale(bench, minutes_list, command):
    # Imported here: tools/bench is the entry point and holds these helpers.
    main = sys.modules["__main__"]
    run, Cost, RunError = main.run, main.Cost, main.RunError
    src = os.path.join(main.DATA, SOURCE)
    work = os.path.join(bench.work, "scale")
    os.makedirs(work, exist_ok=True)
    os.makedirs(os.path.join(bench.out, "plots"), exist_ok=True)
    csv_path = os.path.join(bench.out, "scale.csv")
    rows = []
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS)
        w.writeheader()
        for minutes in minutes_list:
            take = os.path.join(work, "synth_%gmin.c3d" % minutes)
            out = take + ".capz"
            back = os.path.join(work, "back.c3d")
            r = {"minutes": minutes, "note": ""}
            try:
                info = run([bench.tool("capz_synth"), src, take, "--minutes", str(minutes)])
                import json
                meta = json.loads(info)
                r["frames"], r["points"] = meta["frames"], meta["points"]
                r["input_bytes"] = os.path.getsize(take)
                raw = meta["frames"] * meta["points"] * 12
                r["raw_f32_bytes"] = raw
                rd, enc, dec = Cost(), Cost(), Cost()
                run([bench.capz, "info", take], cost=rd)
                r["read_wall_s"], r["read_peak_mb"] = "%.2f" % rd.wall, "%.1f" % (rd.peak_kb / 1024)
                run([bench.capz, "compress", take, "-o", out, "-f", "-q"], cost=enc)
                r["capz_bytes"] = os.path.getsize(out)
                r["bpvf"] = "%.4f" % (8.0 * r["capz_bytes"] / (meta["frames"] * meta["points"]))
                r["enc_wall_s"], r["enc_cpu_s"] = "%.2f" % enc.wall, "%.2f" % enc.cpu
                r["enc_peak_mb"] = "%.1f" % (enc.peak_kb / 1024)
                r["enc_mb_s"] = "%.1f" % (raw / 1e6 / enc.cpu) if enc.cpu else ""
                run([bench.capz, "decompress", out, "-o", back, "-f", "-q"], cost=dec)
                r["dec_wall_s"], r["dec_cpu_s"] = "%.2f" % dec.wall, "%.2f" % dec.cpu
                r["dec_peak_mb"] = "%.1f" % (dec.peak_kb / 1024)
                r["dec_mb_s"] = "%.1f" % (raw / 1e6 / dec.cpu) if dec.cpu else ""
            except RunError as e:
                r["note"] = "FAILED: %s" % e
            for p in (take, out, back):
                if os.path.exists(p):
                    os.unlink(p)
            print("   scale %s" % r, file=sys.stderr)
            w.writerow(r)
            f.flush()
            rows.append(r)
    with open(os.path.join(bench.out, "scale_command.txt"), "w") as f:
        f.write(command + "\n")
    write_scale_report(rows, bench.out, command)


def report_from_csv(out):
    rows = []
    with open(os.path.join(out, "scale.csv"), newline="") as f:
        for r in csv.DictReader(f):
            r["minutes"] = float(r["minutes"])
            if r["frames"]:
                r["frames"] = int(r["frames"])
            rows.append(r)
    with open(os.path.join(out, "scale_command.txt")) as f:
        command = f.read().strip()
    write_scale_report(rows, out, command)


def write_scale_report(rows, out, command):
    lines = ["# capz scale benchmark", "", "Produced by `%s`. Synthetic take from `%s` "
             "(see tools/bench_scale.py): 100 markers, 200 Hz, float C3D; capz defaults." % (
                 command, SOURCE), "",
             "| minutes | frames | input bytes | capz bytes | bpvf | read-only peak MB | encode "
             "s (CPU) | encode peak MB | decode s (CPU) | decode peak MB | enc MB/s | dec MB/s | "
             "note |", "|" + "---|" * 13]
    for r in rows:
        lines.append("| %s |" % " | ".join(str(r.get(k, "")) for k in (
            "minutes", "frames", "input_bytes", "capz_bytes", "bpvf", "read_peak_mb", "enc_cpu_s",
            "enc_peak_mb", "dec_cpu_s", "dec_peak_mb", "enc_mb_s", "dec_mb_s", "note")))
    good = [r for r in rows if not r["note"]]
    if len(good) >= 2:
        a, b = good[0], good[-1]
        df = (b["frames"] - a["frames"]) / 1e6
        for key, what in (("enc_peak_mb", "encode"), ("dec_peak_mb", "decode"),
                          ("read_peak_mb", "read-only")):
            slope = (float(b[key]) - float(a[key])) / df if df else 0
            lines.append("")
            lines.append("%s peak memory grows by %.0f MB per million frames between %g and %g "
                         "minutes." % (what, slope, a["minutes"], b["minutes"]))
        t = (float(b["enc_cpu_s"]) / b["frames"]) / (float(a["enc_cpu_s"]) / a["frames"])
        lines.append("")
        lines.append("Encode CPU time per frame at %g min is %.2fx that at %g min (1.00 = linear)."
                     % (b["minutes"], t, a["minutes"]))
    with open(os.path.join(out, "scale.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    if good:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.5))
        m = [r["minutes"] for r in good]
        ax1.plot(m, [float(r["enc_cpu_s"]) for r in good], "o-", label="encode (CPU s)")
        ax1.plot(m, [float(r["dec_cpu_s"]) for r in good], "s-", label="decode (CPU s)")
        ax1.set_xlabel("take length (minutes at 200 Hz, 100 markers)")
        ax1.set_ylabel("seconds")
        ax2.plot(m, [float(r["enc_peak_mb"]) for r in good], "o-", label="encode peak RSS")
        ax2.plot(m, [float(r["dec_peak_mb"]) for r in good], "s-", label="decode peak RSS")
        ax2.plot(m, [float(r["read_peak_mb"]) for r in good], "^:", label="read only (capz info)")
        ax2.set_xlabel("take length (minutes at 200 Hz, 100 markers)")
        ax2.set_ylabel("MB")
        for ax in (ax1, ax2):
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.grid(True, which="both", alpha=0.25)
            ax.legend(fontsize=8)
        # A flat memory curve must look flat: at least a decade above and below the data.
        top = max(float(r[k]) for r in good for k in ("enc_peak_mb", "dec_peak_mb", "read_peak_mb"))
        low = min(float(r[k]) for r in good for k in ("enc_peak_mb", "dec_peak_mb", "read_peak_mb"))
        ax2.set_ylim(min(low / 3, 10), max(top * 3, 1000))
        fig.suptitle("capz: time and memory against take length")
        fig.text(0.01, 0.01, command, fontsize=7, color="gray")
        fig.tight_layout(rect=(0, 0.03, 1, 0.97))
        fig.savefig(os.path.join(out, "plots", "scale.png"), dpi=110)
        plt.close(fig)
    print("wrote %s" % os.path.join(out, "scale.md"), file=sys.stderr)

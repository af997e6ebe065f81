"""Table (markdown) and plots (PNG) from tools/bench's results.csv. Used by tools/bench."""

import csv
import datetime
import os
import platform
import re

PEERS_ISSUE3 = ["xz -9e", "zstd -19", "fpzip", "zfp -a", "quant+linpred+xz"]
LOSSLESS_PEERS = ["xz -9e", "zstd -19", "fpzip"]


def load(csv_path):
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        r["bytes"] = int(r["bytes"])
        r["total_bytes"] = int(r.get("total_bytes") or r["bytes"])
        for k in ("bpvf", "ratio", "max_error", "max_abs", "rmse", "kg_error", "tol", "enc_cpu_s",
                  "dec_cpu_s", "enc_wall_s", "dec_wall_s", "enc_peak_mb", "dec_peak_mb",
                  "enc_mb_s", "dec_mb_s"):
            try:
                r[k] = float(r[k])
            except (ValueError, KeyError):
                r[k] = None
        r["frames"] = int(r["frames"])
        r["points"] = int(r["points"])
        r["ok"] = r["within"] == "True"
        r["failed"] = r["note"].startswith("FAILED")
    return rows


def best_rows(rows):
    """One row per (input, method, target_kind, target): the smallest that meets the target,
    else the smallest (flagged by ok=False). Variants (layouts, qp) compete within a method."""
    groups = {}
    for r in rows:
        if r["failed"]:
            continue
        groups.setdefault((r["input"], r["method"], r["target_kind"], r["target"]), []).append(r)
    out = []
    for key, rs in groups.items():
        good = [r for r in rs if r["ok"]]
        out.append(min(good or rs, key=lambda r: r["bytes"]))
    return out


def inputs_in_order(rows):
    seen = []
    for r in rows:
        if r["input"] not in seen:
            seen.append(r["input"])
    return seen


def fmt_bytes(n):
    return "{:,}".format(n)


def fmt(v, spec="%.3g"):
    return "" if v is None else spec % v


def machine_note():
    cpu = ""
    try:
        with open("/proc/cpuinfo") as f:
            m = re.search(r"model name\s*:\s*(.*)", f.read())
            cpu = m.group(1).strip() if m else ""
    except OSError:
        pass
    return ("%s, %d cores (shared with other jobs: times are noisy; compare methods within the "
            "same run), %s, python %s" % (cpu or platform.machine(), os.cpu_count() or 0,
                                          platform.platform(), platform.python_version()))


def targets_section(best, rows):
    lines = []
    inputs = inputs_in_order(best)
    capz_methods = sorted({r["method"] for r in best if r["method"].startswith("capz-")})
    if not capz_methods:
        return ["No capz rows in this run (capz compress was not available), so no target can be "
                "judged yet.", ""]
    default = "capz-none" if "capz-none" in capz_methods else capz_methods[0]
    lines += ["### At each tolerance: capz against every peer that met the tolerance", "",
              "Compared sizes in bytes (positions and gap mask, see above); a peer counts only if "
              "its max abs error is within the tolerance, and so does a capz run. The verdict "
              "names the capz codecs smaller than the smallest such peer.", ""]
    head = "| input | tolerance | " + " | ".join(capz_methods) + \
        " | smallest peer (issue 3 list) | smallest peer (all) | capz best / peer best | |"
    lines += [head, "|" + "---|" * (head.count("|") - 1)]
    met_any, met_default = True, True
    for inp in inputs:
        tols = sorted({r["target"] for r in best if r["input"] == inp and
                       r["target_kind"] == "max-error"},
                      key=lambda t: next(r["tol"] for r in best if r["input"] == inp and
                                         r["target"] == t))
        for t in tols:
            cell = {r["method"]: r for r in best if r["input"] == inp and r["target"] == t and
                    r["target_kind"] == "max-error"}
            peers = [r for r in best if r["input"] == inp and not r["method"].startswith("capz-")
                     and (r["target"] == t or r["target_kind"] == "lossless") and r["ok"]]
            p3 = [r for r in peers if r["method"] in PEERS_ISSUE3]
            pbest = min(peers, key=lambda r: r["bytes"]) if peers else None
            p3best = min(p3, key=lambda r: r["bytes"]) if p3 else None
            caps = []
            for m in capz_methods:
                r = cell.get(m)
                caps.append("" if r is None else fmt_bytes(r["bytes"]) + ("" if r["ok"] else
                                                                           " (over!)"))
            okcaps = {m: cell[m] for m in capz_methods if m in cell and cell[m]["ok"]}
            ratio, verdict = None, "?"
            if okcaps and pbest:
                ratio = min(r["bytes"] for r in okcaps.values()) / pbest["bytes"]
                winners = [m[5:] for m, r in okcaps.items() if r["bytes"] < pbest["bytes"]]
                verdict = "met by " + ", ".join(winners) if winners else "MISSED"
            elif pbest:
                verdict = "MISSED"
            met_any &= verdict.startswith("met")
            met_default &= default in okcaps and pbest is not None and \
                okcaps[default]["bytes"] < pbest["bytes"]
            lines.append("| %s | %s | %s | %s | %s | %s | %s |" % (
                inp, t, " | ".join(caps),
                "%s %s" % (p3best["method"], fmt_bytes(p3best["bytes"])) if p3best else "",
                "%s %s" % (pbest["method"], fmt_bytes(pbest["bytes"])) if pbest else "",
                fmt(ratio, "%.2f"), verdict))
    lines += ["", "Every row met by some capz codec: **%s**; by the default codec (%s): **%s**."
              % ("yes" if met_any else "no", default[5:], "yes" if met_default else "no"), ""]

    lines += ["### Lossless: capz --lossless against xz -9e and fpzip", "",
              "| input | " + " | ".join(capz_methods) + " | xz -9e | zstd -19 | fpzip | |",
              "|" + "---|" * (len(capz_methods) + 5)]
    for inp in inputs:
        cell = {r["method"]: r for r in best if r["input"] == inp and r["target_kind"] ==
                "lossless"}
        peers = [cell[m] for m in ("xz -9e", "fpzip") if m in cell]
        verdict = "?"
        if peers:
            pmin = min(p["bytes"] for p in peers)
            winners = [m[5:] for m in capz_methods if m in cell and cell[m]["ok"] and
                       cell[m]["bytes"] < pmin]
            verdict = "met by " + ", ".join(winners) if winners else "MISSED"
        lines.append("| %s | %s | %s |" % (inp, " | ".join(
            (fmt_bytes(cell[m]["bytes"]) + ("" if cell[m]["ok"] else " (not exact!)"))
            if m in cell else "" for m in capz_methods + LOSSLESS_PEERS), verdict))
    lines.append("")

    # Speed on the longest take (the most raw float32 position bytes, frames x points, among the
    # C3D/TRC inputs: frames alone would pick a 2-marker take), one core (CPU seconds).
    takes = [r for r in best if r["format"] in ("c3d", "trc")]
    if takes:
        longest = max(takes, key=lambda r: (r["frames"] * r["points"], r["frames"]))["input"]
        lines += ["### Speed on the longest take (%s): MB/s of raw float32 positions per CPU "
                  "second (target: encode >= 40, decode >= 100)" % longest, "",
                  "| method | target | encode MB/s | decode MB/s | encode wall s | decode wall s "
                  "| |", "|---|---|---|---|---|---|---|"]
        for r in best:
            if r["input"] != longest or not r["method"].startswith("capz-"):
                continue
            v = "met" if (r["enc_mb_s"] or 0) >= 40 and (r["dec_mb_s"] or 0) >= 100 else "MISSED"
            lines.append("| %s | %s | %s | %s | %s | %s | %s |" % (
                r["method"], r["target"], fmt(r["enc_mb_s"], "%.1f"), fmt(r["dec_mb_s"], "%.1f"),
                fmt(r["enc_wall_s"], "%.3f"), fmt(r["dec_wall_s"], "%.3f"), v))
        lines += ["", "Process times include reading the input and writing the output file, "
                  "and process start-up; on a take this small they are dominated by fixed costs.",
                  ""]
    return lines


def input_table(best, rows, inp):
    rs = [r for r in best if r["input"] == inp]
    if not rs:
        return []
    r0 = rs[0]
    lines = ["### %s — %s, %d frames x %d points, units %s, %s storage, %s%% gaps, raw float32 "
             "%s bytes" % (inp, r0["format"], r0["frames"], r0["points"], r0["units"] or "none",
                           r0["storage"], r0["gap_pct"], fmt_bytes(r0["frames"] * r0["points"] *
                                                                   12)), "",
             "| method | variant | target | bytes | whole file | bpvf | ratio | max abs | max err "
             "| RMSE | KG % | enc s | dec s | peak MB enc/dec | within | note |",
             "|" + "---|" * 16]
    order = {"max-error": 0, "kg": 1, "lossless": 2}
    rs.sort(key=lambda r: (order.get(r["target_kind"], 3), r["tol"] or 0, r["method"]))
    for r in rs:
        lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s/%s "
                     "| %s | %s |" % (r["method"], r["variant"], r["target"], fmt_bytes(r["bytes"]),
                                 fmt_bytes(r["total_bytes"]) if r["total_bytes"] != r["bytes"]
                                 else "",
                        fmt(r["bpvf"], "%.3f"), fmt(r["ratio"], "%.2f"), fmt(r["max_abs"]),
                        fmt(r["max_error"]), fmt(r["rmse"]), fmt(r["kg_error"]),
                        fmt(r["enc_cpu_s"], "%.2f"), fmt(r["dec_cpu_s"], "%.2f"),
                        fmt(r["enc_peak_mb"], "%.0f"), fmt(r["dec_peak_mb"], "%.0f"),
                        "yes" if r["ok"] else "NO", r["note"]))
    failed = [r for r in rows if r["input"] == inp and r["failed"]]
    for r in failed:
        lines.append("")
        lines.append("- %s %s %s: %s" % (r["method"], r["target_kind"], r["target"], r["note"]))
    lines.append("")
    return lines


# ---------------------------------------------------------------------------------------------
# Plots

STYLE = {}


def style(method):
    import matplotlib.pyplot as plt
    if method not in STYLE:
        cmap = plt.get_cmap("tab10")
        STYLE[method] = cmap(len(STYLE) % 10)
    return STYLE[method]


def plot_panel(ax, best, inp, xkey, ykey, xlabel, ylabel):
    rs = [r for r in best if r["input"] == inp]
    methods = []
    for r in rs:
        if r["method"] not in methods:
            methods.append(r["method"])
    for m in methods:
        mine = [r for r in rs if r["method"] == m]
        lossy = sorted([r for r in mine if r["target_kind"] == "max-error" and r[xkey]],
                       key=lambda r: r[xkey])
        kg = sorted([r for r in mine if r["target_kind"] == "kg" and r[xkey]],
                    key=lambda r: r[xkey])
        ll = [r for r in mine if r["target_kind"] == "lossless"]
        c = style(m)
        if lossy:
            ax.plot([r[xkey] for r in lossy], [r[ykey] for r in lossy], "o-", color=c, label=m,
                    ms=4, lw=1.4)
        if kg:
            ax.plot([r[xkey] for r in kg], [r[ykey] for r in kg], "s--", color=c, mfc="none",
                    label=m + " (KG target)", ms=5, lw=1)
        for r in ll[:1]:
            ax.axhline(r[ykey], color=c, ls=":", lw=1.2, label=m + " lossless")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.25)


def plot_input(best, inp, path, command):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    r0 = next(r for r in best if r["input"] == inp)
    u = r0["units"] or "data units"
    fig, axes = plt.subplots(1, 2, figsize=(13, 5))
    plot_panel(axes[0], best, inp, "kg_error", "bpvf", "KG error (%)", "bits per vertex per frame")
    plot_panel(axes[1], best, inp, "max_abs", "bytes",
               "max abs error per coordinate (%s)" % u, "compressed bytes")
    handles, labels = axes[1].get_legend_handles_labels()
    fig.legend(handles, labels, loc="center right", fontsize=8, frameon=False)
    fig.suptitle("%s (%d frames x %d points)   lower-left is better" % (inp, r0["frames"],
                                                                       r0["points"]))
    fig.text(0.01, 0.01, command, fontsize=7, color="gray")
    fig.tight_layout(rect=(0, 0.03, 0.83, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_headline(best, inputs, path, command):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(inputs), 2, figsize=(13, 4.6 * len(inputs)), squeeze=False)
    for i, inp in enumerate(inputs):
        r0 = next(r for r in best if r["input"] == inp)
        plot_panel(axes[i][0], best, inp, "kg_error", "bpvf", "KG error (%)",
                   "bits per vertex per frame")
        plot_panel(axes[i][1], best, inp, "max_abs", "bpvf",
                   "max abs error per coordinate (%s)" % (r0["units"] or "data units"),
                   "bits per vertex per frame")
        axes[i][0].set_title("%s (%d x %d)" % (inp, r0["frames"], r0["points"]), fontsize=10)
    handles, labels = {}, {}
    for ax in axes.flat:
        for h, l in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(l, h)
    fig.legend(list(handles.values()), list(handles.keys()), loc="center right", fontsize=8,
               frameon=False)
    fig.suptitle("capz against peers: size against error (lower-left is better)")
    fig.text(0.01, 0.005, command, fontsize=7, color="gray")
    fig.tight_layout(rect=(0, 0.02, 0.83, 0.98))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def headline_inputs(best):
    inputs = inputs_in_order(best)
    fmt_of = {r["input"]: r["format"] for r in best}
    frames = {r["input"]: r["frames"] * r["points"] for r in best}
    c3d = [i for i in inputs if fmt_of[i] in ("c3d", "trc")]
    pcd = [i for i in inputs if fmt_of[i] == "pcd-folder"]
    pick = []
    if c3d:
        pick.append(max(c3d, key=lambda i: frames[i]))
    if pcd:
        pick.append("chickenCrossing" if "chickenCrossing" in pcd else pcd[0])
    return pick or inputs[:2]


def report(csv_path, out, command):
    rows = load(csv_path)
    best = best_rows(rows)
    plots = os.path.join(out, "plots")
    os.makedirs(plots, exist_ok=True)
    lines = ["# capz benchmark results", "",
             "Produced by `%s` on %s." % (command, datetime.datetime.utcnow().strftime(
                 "%Y-%m-%d %H:%M UTC")), "",
             "Machine: " + machine_note() + ".", "",
             "All errors from capz/metrics.h against the original take, valid samples only; "
             "tolerances are per coordinate (max abs); peers' sizes include the gap mask "
             "(bit-packed, xz -9e). Each method's best variant per target (layouts for "
             "zfp/fpzip, qp for draco) is shown; results.csv has every run.", ""]
    lines += ["## Targets (issues 3 and 6)", ""] + targets_section(best, rows)
    lines += ["## Per input", ""]
    for inp in inputs_in_order(best):
        png = os.path.join(plots, re.sub(r"[^A-Za-z0-9_.-]", "_", inp) + ".png")
        plot_input(best, inp, png, command)
        lines += input_table(best, rows, inp)
        lines += ["![%s](plots/%s)" % (inp, os.path.basename(png)), ""]
    head = headline_inputs(best)
    if head:
        plot_headline(best, head, os.path.join(plots, "headline.png"), command)
    with open(os.path.join(out, "results.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote %s, %s and %s" % (csv_path, os.path.join(out, "results.md"), plots))


def update_docs(out, repo, section, md_name, pngs):
    """Copies the PNGs to docs/img/ (prefixed "bench_") and puts the generated markdown (image
    links rewritten) between <!-- SECTION:begin --> and <!-- SECTION:end --> in
    docs/BENCHMARKS.md (the per-input "results" tables: docs/bench/RESULTS.md, images linked from
    there), leaving the rest of the file (other sections) as it is."""
    import shutil
    img = os.path.join(repo, "docs", "img")
    os.makedirs(img, exist_ok=True)
    with open(os.path.join(out, md_name)) as f:
        text = f.read()
    for png in pngs:
        name = "bench_" + os.path.basename(png)
        shutil.copyfile(png, os.path.join(img, name))
        link = "../img/%s" if section == "results" else "img/%s"
        text = text.replace("(plots/%s)" % os.path.basename(png), "(" + link % name + ")")
    # Every heading one level down: the generated title becomes a section of the document.
    text = re.sub(r"^(#+) ", r"#\1 ", text, flags=re.M)
    doc = os.path.join(repo, "docs", "bench", "RESULTS.md") if section == "results" else \
        os.path.join(repo, "docs", "BENCHMARKS.md")
    begin, end = "<!-- %s:begin -->" % section, "<!-- %s:end -->" % section
    body = "%s\n<!-- generated by tools/bench: edit the script, not this block -->\n%s%s" % (
        begin, text, end)
    old = open(doc).read() if os.path.exists(doc) else "# capz benchmarks\n"
    if begin in old and end in old:
        new = old[:old.index(begin)] + body + old[old.index(end) + len(end):]
    else:
        new = old.rstrip("\n") + "\n\n" + body + "\n"
    with open(doc, "w") as f:
        f.write(new)
    print("updated %s (%s)" % (doc, section))

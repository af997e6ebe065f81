#!/usr/bin/env python3
"""Writes comma-separated TRC files (issue #38, item 1) from OpenSim's tab-separated ones, as
other tools write them:

  NAME.sheet.trc       a spreadsheet's CSV re-save: every field kept as text, tabs become commas,
                       every line padded with commas to the widest line's field count;
  NAME.sheet-crlf.trc  the same with CRLF line ends (a spreadsheet on Windows);
  NAME.sheet-gen.trc   a spreadsheet that re-printed the numbers in its "General" format (the
                       shortest decimal: 12.50000 -> 12.5, 0.00000 -> 0, -0.0 -> 0), CRLF;
  NAME.pyomeca.trc     pyomeca's test-data shape (pyomeca/pyomeca tests/data/markers.trc): the
                       rates written as integers when whole, numbers in the shortest decimal,
                       rows without OpenSim's closing tab, every line padded to the widest, the
                       blank line after line 5 all commas, LF line ends.

The source is parsed as OpenSim writes it: five header lines, a blank line, then one row per
frame, fields separated by tabs. Nothing is random: running this again writes the same bytes.

usage: python3 data/make_comma_trc.py SOURCE.trc... -o OUTDIR
       (data/comma_trc/ holds what `python3 data/make_comma_trc.py data/std_walking5_markers.trc
        -o data/comma_trc` writes; tools/bench_comma_trc.sh makes the others from
        ../shared/data/trc/opensim)
"""
import argparse
import os
import re

NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


def general(text):
    """A spreadsheet's "General" spelling of a decimal field: the shortest decimal that reads
    back as the same double, without trailing zeros, "-0" as "0"; other text unchanged."""
    t = text.strip()
    if not NUMBER.match(t):
        return text
    v = float(t)
    if v == 0:
        return "0"
    s = repr(v)
    if "e" in s or "E" in s:
        return s
    if s.endswith(".0"):
        s = s[:-2]
    return s


def read_lines(path):
    with open(path, "rb") as f:
        text = f.read().decode("latin-1")
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    return [l[:-1] if l.endswith("\r") else l for l in lines]


def padded(rows, ending):
    width = max(len(r) for r in rows)
    return "".join(",".join(r + [""] * (width - len(r))) + ending for r in rows)


def sheet(lines, numbers, ending):
    rows = [l.split("\t") for l in lines]
    if numbers:
        rows = rows[:2] + [[general(f) for f in r] for r in rows[2:3]] + rows[3:5] + \
            [[general(f) for f in r] for r in rows[5:]]
    return padded(rows, ending)


def pyomeca(lines):
    rows = [l.split("\t") for l in lines]
    out = []
    for i, r in enumerate(rows):
        while len(r) > 1 and r[-1] == "":
            r = r[:-1]  # OpenSim's closing tab; the padding gives the width back
        if i == 0 or i == 1 or i == 3 or i == 4:
            out.append(r)
        else:
            out.append([general(f) for f in r])
    width = max(len(r) for r in out)
    # Line 4 names a marker every three columns: its last two columns are empty, as pyomeca's.
    names = out[3]
    out[3] = names + [""] * (width - len(names))
    return padded(out, "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("sources", nargs="+")
    ap.add_argument("-o", "--out", required=True)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    for src in args.sources:
        lines = read_lines(src)
        stem = os.path.splitext(os.path.basename(src))[0]
        variants = {
            "sheet": sheet(lines, False, "\n"),
            "sheet-crlf": sheet(lines, False, "\r\n"),
            "sheet-gen": sheet(lines, True, "\r\n"),
            "pyomeca": pyomeca(lines),
        }
        for name, text in variants.items():
            path = os.path.join(args.out, "%s.%s.trc" % (stem, name))
            with open(path, "wb") as f:
                f.write(text.encode("latin-1"))
            print(path, len(text))


if __name__ == "__main__":
    main()

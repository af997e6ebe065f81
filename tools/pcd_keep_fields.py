#!/usr/bin/env python3
"""Copies a folder of binary PCD frames keeping only some fields (issue 15's peer comparisons).

  pcd_keep_fields.py IN_DIR OUT_DIR FIELD [FIELD ...]

Every *.pcd of IN_DIR is written to OUT_DIR with the named fields only (in the file's order;
x y z must be named), the same WIDTH / HEIGHT / VIEWPOINT / POINTS and each kept value's bytes
unchanged (NaN points stay). Only DATA binary frames are handled (what make_scan_sequences.py
writes); anything else is an error.
"""
import os
import sys

import numpy as np


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    src, dst, keep = sys.argv[1], sys.argv[2], sys.argv[3:]
    os.makedirs(dst, exist_ok=True)
    names = sorted(n for n in os.listdir(src) if n.endswith(".pcd"))
    if not names:
        sys.exit("pcd_keep_fields: no .pcd in " + src)
    for name in names:
        with open(os.path.join(src, name), "rb") as f:
            data = f.read()
        head, pos = {}, 0
        lines = []
        while True:
            e = data.index(b"\n", pos)
            line = data[pos:e].decode("ascii")
            pos = e + 1
            lines.append(line)
            w = line.split()
            if w and not w[0].startswith("#"):
                head[w[0]] = w[1:]
            if w and w[0] == "DATA":
                break
        if head["DATA"] != ["binary"]:
            sys.exit("pcd_keep_fields: %s: only DATA binary is handled" % name)
        fields, sizes = head["FIELDS"], [int(s) for s in head["SIZE"]]
        counts = [int(c) for c in head.get("COUNT", ["1"] * len(fields))]
        missing = [k for k in keep if k not in fields]
        if missing:
            sys.exit("pcd_keep_fields: %s has no field %s" % (name, " ".join(missing)))
        width = [s * c for s, c in zip(sizes, counts)]
        offset = [sum(width[:i]) for i in range(len(fields))]
        stride = sum(width)
        n = int(head["POINTS"][0])
        body = data[pos:pos + n * stride]
        if len(body) != n * stride:
            sys.exit("pcd_keep_fields: %s is truncated" % name)
        kept = [i for i, f in enumerate(fields) if f in keep]
        rows = np.frombuffer(body, dtype=np.uint8).reshape(n, stride)
        out = np.concatenate([rows[:, offset[i]:offset[i] + width[i]] for i in kept], axis=1)
        pick = {"FIELDS": fields, "SIZE": head["SIZE"], "TYPE": head["TYPE"],
                "COUNT": head.get("COUNT", ["1"] * len(fields))}
        text = []
        for line in lines:
            w = line.split()
            if w and w[0] in pick:
                line = " ".join([w[0]] + [pick[w[0]][i] for i in kept])
            text.append(line)
        with open(os.path.join(dst, name), "wb") as f:
            f.write(("\n".join(text) + "\n").encode("ascii") + out.tobytes())


if __name__ == "__main__":
    main()

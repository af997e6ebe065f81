#!/usr/bin/env bash
# Point-field sequences (issue #15): capz at a bound against the peers that code point clouds
# with attributes, on the same frames as tools/fields_bench.sh:
#   - Draco (build/tools/capz_draco, libdraco in-process, one point cloud per frame): every
#     field as an attribute, float fields raw (--floats raw) or as their uint32 bit patterns
#     (--floats bits); and on folders reduced to x y z rgb (depth) / x y z (lidar);
#   - PCL's OctreePointCloudCompression (build/tools/capz_octree pcd): x y z rgb with colour
#     (depth), x y z (lidar).
# capz runs on the same folder the peer reads (tools/pcd_keep_fields.py makes the reduced ones),
# with --max-error B (B in the data's units, per coordinate, default 0.001), each archive
# checked by `capz verify` against its folder. Each peer is held to B per coordinate too (its
# position error measured on the decoded frames; see the tools' headers for how).
#
#   tools/fields_peers_bench.sh BUILD_DIR [SHARED_DATA] [WORKDIR] [B]
#   tools/fields_peers_bench.sh BUILD_DIR --smoke [WORKDIR]   (tiny sequences: a check that
#                                                             every tool runs; ctest runs it)
# Without WORKDIR the sequences go to a temporary folder, removed at the end. The script fails
# when a tool fails, an archive fails `capz verify`, or a peer misses the bound.
#
# Prints a markdown table, one row per sequence and peer.
set -euo pipefail
build=$(readlink -f "$1")
here=$(dirname "$(readlink -f "$0")")
smoke=0
shared=${2:-$here/../../shared/data}
if [ "$shared" = "--smoke" ]; then
  smoke=1
fi
if [ -n "${3:-}" ]; then
  work=$3
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
bound=${4:-0.001}
py=/usr/bin/python3
capz="$build/capz"
draco="$build/tools/capz_draco"
octree="$build/tools/capz_octree"
for t in "$capz" "$draco" "$octree"; do
  [ -x "$t" ] || { echo "fields_peers_bench: $t is not built" >&2; exit 1; }
done
mkdir -p "$work"
if [ $smoke = 1 ]; then
  # A tiny depth sequence needs a mesh: a few frames of a synthetic one.
  mesh="$work/mesh"
  if [ ! -d "$mesh" ]; then
    mkdir -p "$mesh"
    $py - "$mesh" <<'PY'
import math, os, struct, sys
for f in range(3):
    pts = [(math.cos(u) * (1 + 0.3 * math.cos(v)), math.sin(u) * (1 + 0.3 * math.cos(v)),
            0.3 * math.sin(v) + 0.01 * f) for u in [i * 0.2 for i in range(32)]
           for v in [j * 0.4 for j in range(16)]]
    with open(os.path.join(sys.argv[1], "m%02d.pcd" % f), "wb") as o:
        o.write(("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH %d\n"
                 "HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA binary\n"
                 % (len(pts), len(pts))).encode())
        for p in pts:
            o.write(struct.pack("<3f", *p))
PY
  fi
  [ -d "$work/depth" ] || $py "$here/make_scan_sequences.py" depth "$mesh" "$work/depth" --frames 3 --width 40 --height 30
  [ -d "$work/lidar" ] || $py "$here/make_scan_sequences.py" lidar "$work/lidar" --frames 3 --rings 4 --steps 90
else
  [ -d "$work/depth" ] || $py "$here/make_scan_sequences.py" depth "$shared/pcd/horse-gallop" "$work/depth" --frames 40 --width 160 --height 120
  [ -d "$work/lidar" ] || $py "$here/make_scan_sequences.py" lidar "$work/lidar" --frames 40 --rings 16 --steps 720
fi
[ -d "$work/depth_rgb" ] || $py "$here/pcd_keep_fields.py" "$work/depth" "$work/depth_rgb" x y z rgb
[ -d "$work/lidar_xyz" ] || $py "$here/pcd_keep_fields.py" "$work/lidar" "$work/lidar_xyz" x y z

# capz bytes of a folder at the bound, the archive checked against the folder (once a folder).
capz_bytes() {
  local a="$work/$(basename "$1")_$bound.capz"
  if [ ! -f "$a.verified" ]; then
    "$capz" compress "$1" -o "$a" -f --max-error "$bound" -q
    "$capz" verify "$a" --against "$1" -q
    touch "$a.verified"
  fi
  stat -c %s "$a"
}

echo "| sequence | fields kept (peer and capz) | peer | peer bytes | peer settings | peer position error (max per coordinate) | peer attribute error | peer drops | capz --max-error $bound | capz / peer |"
echo "|---|---|---|---|---|---|---|---|---|---|"
row() {  # row SEQUENCE FOLDER PEER JSON
  local cz
  cz=$(capz_bytes "$2")
  $py - "$@" "$cz" "$bound" <<'PY'
import json, sys
seq, folder, peer, js, cz, bound = sys.argv[1:]
j, cz, bound = json.loads(js), int(cz), float(bound)
with open(folder + "/" + sorted(__import__("os").listdir(folder))[0], "rb") as f:
    fields = next(l for l in f.read(4096).split(b"\n") if l.startswith(b"FIELDS")).split()[1:]
fields = " ".join(x.decode() for x in fields)
dropped = j["points"] - j["kept_points"]
drops = "%d NaN points (%.0f%%)" % (dropped, 100 * dropped / j["points"]) if dropped else "nothing"
if j["organized_dropped"]:
    drops += ", the organized layout"
if "attributes" in j:  # capz_draco
    nn = j["correspondence"] == "nearest"
    how = "nearest decoded point (kd-tree reorders)" if nn else "point order kept"
    settings = "qp %d-%d, %s coder" % (j["bits_min"], j["bits_max"],
                                        "kd-tree" if j["kd_tree_frames"] else "sequential")
    attrs = []
    for a in j["attributes"]:
        if a["exact_points"] == a["points"]:
            attrs.append("%s exact" % a["name"])
        elif a["multiset_exact"]:
            attrs.append("%s exact per frame as a multiset; on the pairing max abs diff %.3g"
                         % (a["name"], a["max_abs"]))
        else:
            attrs.append("%s max abs diff %.3g (%d of %d points exact)"
                         % (a["name"], a["max_abs"], a["exact_points"], a["points"]))
    attr = "; ".join(attrs) or "-"
    if attrs:
        drops += "; field names"
else:  # capz_octree pcd
    how = "nearest decoded point (octree reorders)"
    settings = "point res %.3g, octree res 16x" % j["point_res"]
    if j["colour"]:
        kept = j["kept_points"]
        if j["colour_exact_points"] == kept:
            attr = "rgb exact"
        else:
            attr = "rgb %s; on the pairing max abs diff %g, %.1f%% of points exact" % (
                "exact per frame as a multiset" if j["colour_multiset_exact"] else "not exact",
                j["colour_max_abs"], 100 * j["colour_exact_points"] / kept)
        drops += "; alpha (differs at %d points); the NaN points' colours" % j["alpha_differs_points"]
    else:
        attr = "-"
    if j["decoded_points"] != j["kept_points"]:
        drops += "; decodes %d of %d points" % (j["decoded_points"], j["kept_points"])
err = "%.3g (Euclidean %.3g), %s" % (j["pos_max_abs"], j["pos_max_euclid"], how)
if j["pos_max_abs"] > bound:
    err += " **above B**"
print(f"| {seq} | {fields} | {peer} | {j['bytes']:,} | {settings} | {err} | {attr} | {drops} | {cz:,} | {cz / j['bytes']:.3f} |")
if j["pos_max_abs"] > bound:
    sys.exit("fields_peers_bench: %s did not meet the bound on %s" % (peer, folder))
PY
}
for s in depth lidar; do
  d="$work/$s"
  j=$("$draco" "$d" --max-error "$bound" --floats raw)
  row $s "$d" "Draco, float fields raw" "$j"
  j=$("$draco" "$d" --max-error "$bound" --floats bits)
  row $s "$d" "Draco, float fields as uint32 bits" "$j"
done
j=$("$draco" "$work/depth_rgb" --max-error "$bound")
row depth "$work/depth_rgb" "Draco" "$j"
j=$("$octree" pcd "$work/depth_rgb" --max-error "$bound" --color)
row depth "$work/depth_rgb" "PCL octree, colour" "$j"
j=$("$draco" "$work/lidar_xyz" --max-error "$bound")
row lidar "$work/lidar_xyz" "Draco" "$j"
j=$("$octree" pcd "$work/lidar_xyz" --max-error "$bound")
row lidar "$work/lidar_xyz" "PCL octree" "$j"

#!/usr/bin/env python3
"""Makes the golden streams of a new format version (CONTRIBUTING.md, "Adding a golden stream").

Run from the repository root, after building:
    python3 tests/golden/make_newest.py build/capz build/tests/capz_golden_tests 5.0 [SOURCE ...]

With SOURCE names (as MANIFEST.txt's second column, e.g. lidar_small), only the streams of those
sources are remade, each from its own newest stream's options (8.0 for C3D takes remakes their
5.0 and 7.0 streams): a version the encoder writes only for some takes (6.0 for normals or
organized fields, 7.0 for scans along sensor rays, unorganized clouds' fields or repeated analog
frames, 8.0 for C3D parameters after the format's dictionary or analog channels) gets streams of
those takes
only, and the check the tool runs fails if the encoder wrote another version than the tag says.

For every MANIFEST.txt line of the newest version already listed that records its options, the
CLI makes the same stream as `capz compress data/SOURCE -o STREAM OPTIONS` under the new version
tag, and the line is appended with the CRC-32C of the decoded take, which capz_golden_tests
reports ("decoded content changed: now XXXXXXXX") for a line appended with a placeholder. Lines of
the new version already present are replaced: run it only while that version is being written
(never on a version that has shipped). Existing streams of older versions are never touched."""
import os, re, subprocess, sys

cli, golden_test, version = sys.argv[1], sys.argv[2], sys.argv[3]
only = set(sys.argv[4:])
root = os.path.dirname(os.path.abspath(__file__))
streams = os.path.join(root, 'streams')
manifest = os.path.join(streams, 'MANIFEST.txt')
data = os.path.join(os.path.dirname(os.path.dirname(root)), 'data')

lines = open(manifest).read().splitlines()
tag = '.v' + version + '.capz'
# Streams of the new version with no older counterpart (made by hand for what only the new
# version carries, e.g. PCD fields in 5.0) are kept as they are; the others are remade.
older = set()
for l in lines:
    w = l.split()
    if l.startswith('#') or len(w) < 4 or w[0].endswith(tag):
        continue
    older.add(re.sub(r'\.v\d+\.\d+\.capz$', '', w[0]))
kept, entries = [], []
for l in lines:
    w = l.split()
    if not l.startswith('#') and w and w[0].endswith(tag) and w[0][:-len(tag)] in older:
        continue  # remade below
    kept.append(l)
    if l.startswith('#') or len(w) < 4 or w[0].endswith(tag):
        continue
    entries.append(w)
versions = sorted({re.search(r'\.v(\d+)\.(\d+)\.capz$', e[0]).groups() for e in entries},
                  key=lambda v: (int(v[0]), int(v[1])))
newest = '.v%s.%s.capz' % versions[-1]
ver_of = lambda e: tuple(int(x) for x in re.search(r'\.v(\d+)\.(\d+)\.capz$', e[0]).groups())
# Per source and options, its newest stream: with SOURCE names each of theirs is remade (a take
# whose version rises from 5.0 to 8.0 skips those between); without, the newest version's.
latest = {}
for e in entries:
    key = (e[1], tuple(e[3:]))
    if key not in latest or ver_of(e) > ver_of(latest[key]):
        latest[key] = e
made = []
for e in entries:
    if only:
        if e[1] not in only or latest[(e[1], tuple(e[3:]))] is not e:
            continue
    elif not e[0].endswith(newest):
        continue
    old_tag = re.search(r'\.v\d+\.\d+\.capz$', e[0]).group(0)
    # A remade stream of a shipped version (NAME.rN.vX.Y, the manifest's header) drops its rN.
    name = re.sub(r'\.r\d+$', '', e[0][:-len(old_tag)]) + tag
    out = os.path.join(streams, name)
    subprocess.run([cli, 'compress', os.path.join(data, e[1]), '-o', out, '-f', '-q'] + e[3:],
                   check=True)
    with open(out, 'rb') as f:
        head = f.read(11)
    if '%d.%d' % (head[9], head[10]) != version:
        os.remove(out)
        sys.exit('%s: the encoder wrote version %d.%d, not %s' % (name, head[9], head[10], version))
    made.append([name, e[1], '00000000'] + e[3:])
open(manifest, 'w').write('\n'.join(kept + [' '.join(m) for m in made]) + '\n')
r = subprocess.run([golden_test, '--gtest_filter=Golden.GivenGoldenStreamsWhenDecoded*'],
                   capture_output=True, text=True)
crc = {}
pending = None  # gtest prints the failure, then the trace line naming the stream
for l in r.stdout.splitlines():
    c = re.search(r'decoded content changed: now ([0-9a-f]{8})', l)
    if c:
        pending = c.group(1)
    s = re.search(r'test_golden\.cpp:\d+: (\S+\.capz)$', l)
    if s and pending:
        crc[s.group(1)] = pending
        pending = None
for m in made:
    if m[0] not in crc:
        sys.exit('no CRC reported for ' + m[0] + ':\n' + r.stdout[-3000:])
    m[2] = crc[m[0]]
open(manifest, 'w').write('\n'.join(kept + [' '.join(m) for m in made]) + '\n')
print('made %d streams of version %s' % (len(made), version))

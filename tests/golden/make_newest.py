#!/usr/bin/env python3
"""Makes the golden streams of the format version being written (CONTRIBUTING.md, "Adding a
golden stream").

Run from the repository root, after building:
    python3 tests/golden/make_newest.py build/capz build/tests/capz_golden_tests 1.0 [SOURCE ...]

Every MANIFEST.txt line of that version that records options is remade: the CLI makes the same
stream as `capz compress data/SOURCE -o STREAM OPTIONS`, its `check` column is set from what the
stream holds (`bytes` without a transform codec, else `content`: see the manifest's header), and its CRC-32C of the decoded take is filled in from what capz_golden_tests reports
("decoded content changed: now XXXXXXXX"). With SOURCE names (the second column), only those
sources' lines are remade. Run it only while the version is being written, never on a version
that has shipped; lines of other versions are never touched."""
import os, re, struct, subprocess, sys

cli, golden_test, version = sys.argv[1], sys.argv[2], sys.argv[3]
only = set(sys.argv[4:])
root = os.path.dirname(os.path.abspath(__file__))
streams = os.path.join(root, 'streams')
manifest = os.path.join(streams, 'MANIFEST.txt')
data = os.path.join(os.path.dirname(os.path.dirname(root)), 'data')
major, minor = (int(x) for x in version.split('.'))
tag = '.v' + version + '.capz'


def chunks(b):
    """(type, payload) of every chunk after the 15-byte file header."""
    out, off = [], 15
    while off + 12 <= len(b):
        n = struct.unpack('<I', b[off + 4:off + 8])[0]
        out.append((b[off:off + 4].decode('ascii', 'replace'), b[off + 8:off + 8 + n]))
        off += 12 + n
    return out


def varint_end(p, i):
    """The offset after the varint at p[i]."""
    while p[i] & 0x80:
        i += 1
    return i + 1


def raw_window(p):
    """Whether an SCNW payload is a raw window (gaps bit 1: LZMA2 of the bits, FORMAT.md)."""
    return p[varint_end(p, varint_end(p, 0))] & 2 != 0


def check_of(b):
    """'bytes' for a stream whose positions come from integer paths only (no transform codec,
    no raw window, whose SCNW the system's LZMA decides: the manifest's header), else
    'content'."""
    cs = chunks(b)
    head = dict((t, p) for t, p in reversed(cs))['HEAD']
    raw = any(raw_window(p) for t, p in cs if t == 'SCNW')
    return 'bytes' if head[18] == 0 and not raw else 'content'


lines = open(manifest).read().splitlines()
made = []
for i, l in enumerate(lines):
    w = l.split()
    if l.startswith('#') or len(w) < 5 or not w[0].endswith(tag) or (only and w[1] not in only):
        continue
    out = os.path.join(streams, w[0])
    subprocess.run([cli, 'compress', os.path.join(data, w[1]), '-o', out, '-f', '-q'] + w[4:],
                   check=True)
    b = open(out, 'rb').read()
    if (b[9], b[10]) != (major, minor):
        os.remove(out)
        sys.exit('%s: the encoder wrote version %d.%d, not %s' % (w[0], b[9], b[10], version))
    w[2], w[3] = '00000000', check_of(b)
    lines[i] = ' '.join(w)
    made.append(i)
open(manifest, 'w').write('\n'.join(lines) + '\n')
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
for i in made:
    w = lines[i].split()
    if w[0] not in crc:
        sys.exit('no CRC reported for ' + w[0] + ':\n' + r.stdout[-3000:])
    w[2] = crc[w[0]]
    lines[i] = ' '.join(w)
open(manifest, 'w').write('\n'.join(lines) + '\n')
print('made %d streams of version %s' % (len(made), version))

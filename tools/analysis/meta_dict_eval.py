#!/usr/bin/env python3
"""What does META coding 3 give takes whose software its dictionary has not seen?
(analysis only, not part of capz; the findings are in docs/lab/2026-11-25-whole-takes-and-meta.md)

  meta_dict_eval.py BUILD_DIR OUT.tsv FILE.c3d ...

Dictionary 1 was made from the shared C3D files (tools/make_meta_dict.py), so on those files it
knows each take's own folder-mates: a take's size with it is in-sample. This script measures
the out-of-sample figure: the files are grouped by folder (a c3d.org sample folder, a BTK data
folder: one lab's or one program's takes), and each group's META is coded after a dictionary
made, the same way, from every other group only. Per file it compresses the take at the defaults
and with --lossless (BUILD_DIR/capz), and writes one row:

  file  bytes  xz9e  default  lossless  meta_lzma2  meta_dict1  meta_heldout
  default_heldout  lossless_heldout

meta_*: META's payload with coding 2, with coding 3 after dictionary 1, and with coding 3 after
the held-out dictionary (BUILD_DIR/tools/capz_meta_dict); *_heldout: the .capz with its META
replaced by the smaller of coding 2 and the held-out coding 3 (what the encoder would write had
dictionary 1 been made without the take's folder). The last lines summarise the whole-take
targets of issue #13 with dictionary 1 and held out.
"""
import collections
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, capture_output=True, **kw)


def xz_size(path):
    with open(path, 'rb') as f:
        return len(run(['xz', '-9e', '-c'], stdin=f).stdout)


def meta_rows(tool, files, dict_path):
    out = run([tool, '--dict', dict_path] + files).stdout.decode()
    rows = {}
    for line in out.splitlines():
        if line.startswith('total '):
            continue
        f = line.split('\t')
        rows[f[0]] = (int(f[1]), int(f[4]), int(f[5]), int(f[6]))
    return rows


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    build, out_tsv, files = argv[0], argv[1], argv[2:]
    capz = os.path.join(build, 'capz')
    tool = os.path.join(build, 'tools', 'capz_meta_dict')
    groups = collections.defaultdict(list)
    for f in files:
        groups[os.path.dirname(os.path.abspath(f))].append(f)
    result = {}
    with tempfile.TemporaryDirectory() as tmp:
        for gi, (folder, members) in enumerate(sorted(groups.items())):
            others = [f for g, m in groups.items() if g != folder for f in m]
            dict_path = os.path.join(tmp, 'heldout.bin')
            run([sys.executable, os.path.join(HERE, 'make_meta_dict.py'), dict_path,
                 '--min-files', '2'] + others)
            streams = {}
            for i, f in enumerate(members):
                for mode in ('default', 'lossless'):
                    s = os.path.join(tmp, f'{gi}_{i}_{mode}.capz')
                    extra = ['--lossless'] if mode == 'lossless' else []
                    try:
                        run([capz, 'compress', f, '-o', s, '-f', '-q'] + extra)
                    except subprocess.CalledProcessError:
                        s = None
                    streams[(f, mode)] = s
            for mode in ('default', 'lossless'):
                paths = [streams[(f, mode)] for f in members if streams[(f, mode)]]
                if not paths:
                    continue
                rows = meta_rows(tool, paths, dict_path)
                for f in members:
                    s = streams[(f, mode)]
                    if not s:
                        continue
                    payload, lz, d1, held = rows[s]
                    size = os.path.getsize(s)
                    r = result.setdefault(f, {})
                    r[mode] = size
                    r[mode + '_heldout'] = size - payload + min(lz, held)
                    r['meta'] = (lz, d1, held)
            for f in members:
                if f in result:
                    result[f]['bytes'] = os.path.getsize(f)
                    result[f]['xz'] = xz_size(f)
    cols = ['bytes', 'xz', 'default', 'lossless']
    with open(out_tsv, 'w') as o:
        o.write('file\tbytes\txz9e\tdefault\tlossless\tmeta_lzma2\tmeta_dict1\tmeta_heldout\t'
                'default_heldout\tlossless_heldout\n')
        for f in files:
            r = result.get(f)
            if not r or 'default' not in r or 'lossless' not in r:
                continue
            o.write('\t'.join([f] + [str(r[c]) for c in cols] + [str(v) for v in r['meta']] +
                              [str(r['default_heldout']), str(r['lossless_heldout'])]) + '\n')
    # Issue #13's whole-take targets: >= 100 KB: defaults 0.6x, lossless 0.8x; smaller: 0.8x.
    big = [r for r in result.values() if 'default' in r and 'lossless' in r and
           r['bytes'] >= 100 * 1024]
    small = [r for r in result.values() if 'default' in r and 'lossless' in r and
             r['bytes'] < 100 * 1024]
    for label, rs, key, target in (('>= 100 KB, defaults', big, 'default', 0.6),
                                   ('>= 100 KB, --lossless', big, 'lossless', 0.8),
                                   ('< 100 KB, defaults', small, 'default', 0.8)):
        for suffix, name in (('', 'dictionary 1'), ('_heldout', 'held out')):
            x = [r[key + suffix] / r['xz'] for r in rs]
            if not x:
                continue
            met = sum(v <= target for v in x)
            print(f'{label:24s} {name:13s} median {statistics.median(x):.3f} worst {max(x):.3f} '
                  f'{met} of {len(x)} <= {target}')
    lz = sum(r['meta'][0] for r in result.values() if 'meta' in r)
    d1 = sum(r['meta'][1] for r in result.values() if 'meta' in r)
    ho = sum(r['meta'][2] for r in result.values() if 'meta' in r)
    print(f'META payloads, {len(result)} takes: coding 2 {lz}, dictionary 1 {d1} '
          f'({d1 / lz:.3f}), held out {ho} ({ho / lz:.3f})')


if __name__ == '__main__':
    main(sys.argv[1:])

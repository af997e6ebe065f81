#!/usr/bin/env python3
"""Which analog channels keep a take above 0.85x its best peer, and by how many bytes?
(analysis only, not part of capz; the findings are in docs/lab/2026-11-27-analog-misses.md)

    tools/analysis/analog_misses.py build/tools/capz_analog_bench FILE.c3d ...

Runs the bench with its peers on every file, then `--per-channel` on the takes above 0.85x the
best peer, and prints a Markdown table with one row per such take, worst first, and a class:

  c  float channels (kinds f32/f64) hold more than half the take's bytes (coded alone);
  a  entropy-bound: capz is within 6% of the order-0 token entropy (`Htok`: bit-length tokens
     plus raw bits, of the best of the samples, their differences, the LPC and cascade
     residuals) on the integer channels, even every integer channel at min(capz, Htok) stays
     above 0.85x the best peer ("floor"), and no peer of a channel alone beats capz on channels
     worth more than 3% of the take;
  b  the rest: capz loses somewhere by a margin. The per-channel peers say where: "xz" when xz
     of the channel alone beats capz by the most bytes (repeats, held values, tables), "flac"
     when flac or wavpack does (prediction), "-" when no peer beats capz on channels worth 3% of
     the take (capz wins each channel, but by less than 15%).

Figures in bytes; "capz" is the take coded whole (channels together), "alone" the channels
coded one by one (no inter-channel reference).
"""
import collections
import subprocess
import sys


def run(cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.splitlines()


def takes(lines, files):
    """The bench's per-take rows: path -> (capz, best peer, best peer's name, ratio)."""
    out = {}
    for line in lines:
        if line.startswith('take') or line.startswith('takes'):
            continue
        name, r = line[:48].strip(), line[48:].split()
        path = next(f for f in files if f.endswith(name))
        peers = dict(zip(('xz', 'zstd', 'fpzip', 'flac', 'wavpack'), map(int, r[4:9])))
        best = min((v, k) for k, v in peers.items() if v > 0)
        out[path] = (int(r[3]), best[0], best[1], float(r[9]))
    return out


def channels(lines):
    """--per-channel rows: take name (last 40 characters) -> list of channel dicts."""
    out = collections.OrderedDict()
    keys = ('capz', 'hx', 'hd1', 'hd2', 'hlpc', 'hlms', 'htok', 'flac', 'wv', 'xz')
    for line in lines:
        if not line.startswith('CH ') or line.startswith('CH take'):
            continue
        name, r = line[3:43].strip(), line[43:].split()
        ch = dict(zip(keys, map(float, r[3:])))
        ch['kind'] = r[2]
        out.setdefault(name, []).append(ch)
    return out


def main():
    bench, files = sys.argv[1], sys.argv[2:]
    whole = takes(run([bench] + files), files)
    missed = sorted((p for p in whole if whole[p][3] > 0.85), key=lambda p: -whole[p][3])
    per = channels(run([bench, '--per-channel'] + missed))
    print('| take | ch | capz | best peer | ratio | float | int (alone) | Htok int | capz/Htok '
          '| floor | xz wins | flac/wv wins | class |')
    print('|---|---|---|---|---|---|---|---|---|---|---|---|---|')
    count = collections.Counter()
    for path in missed:
        capz, best, peer, ratio = whole[path]
        chs = next(v for k, v in per.items() if path.endswith(k))
        alone = sum(c['capz'] for c in chs)
        flt = sum(c['capz'] for c in chs if c['kind'] in ('f32', 'f64'))
        ints = [c for c in chs if c['htok'] >= 0 and c['kind'] not in ('f32', 'f64')]
        ti = sum(c['capz'] for c in ints)
        ht = sum(c['htok'] for c in ints)
        floor = (alone - ti + sum(min(c['capz'], c['htok']) for c in ints)) * capz / alone / best
        xzwin = sum(max(0, c['capz'] - c['xz']) for c in chs if c['xz'] > 0)
        flwin = sum(max(0, c['capz'] - min(v for v in (c['flac'], c['wv']) if v > 0))
                    for c in chs if c['flac'] > 0)
        over = ti / ht if ht else 0
        if flt > 0.5 * alone:
            cls = 'c'
        elif floor > 0.85 and over < 1.06 and max(xzwin, flwin) <= 0.03 * alone:
            cls = 'a'
        elif max(xzwin, flwin) > 0.03 * alone:
            cls = 'b xz' if xzwin >= flwin else 'b flac'
        else:
            cls = 'b -'
        count[cls[0]] += 1
        name = path.split('/data/c3d/')[-1]
        print('| %s | %d | %d | %d %s | %.3f | %d | %d | %.0f | %.3f | %.3f | %d | %d | %s |' %
              (name, len(chs), capz, best, peer, ratio, flt, ti, ht, over, floor, xzwin, flwin,
               cls))
    print()
    print('takes above 0.85x: %d; a %d, b %d, c %d' % (len(missed), count['a'], count['b'],
                                                       count['c']))


if __name__ == '__main__':
    main()

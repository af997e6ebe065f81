"""Tables and the rate-distortion plot of the scan benchmark (tools/scan_bench) from its rows
(dicts with scan_bench.COLUMNS, as written to the TSV).

  report.py TSV [--plot PNG] [--md FILE]    (re-renders from a TSV without rerunning)
"""
import argparse
import csv
import sys

GPCC = ('gpcc-octree', 'gpcc-angular', 'gpcc-angular-az', 'gpcc-octree-inter',
        'gpcc-octree-angular', 'gpcc-octree-angular-inter')
ORDER = GPCC + ('cloudini', 'draco', 'pcl-octree', 'capz', 'capz-any', 'capz-lossless', 'xz-9e',
                'zstd-19', 'xz-9e-xyz')
MULTI = ('pandar64-factory20', 'robosense-e1', 'robosense-helios16p')


def _f(r, k):
    try:
        return float(r[k])
    except (KeyError, ValueError, TypeError):
        return None


def bound_label(b):
    b = float(b)
    return '%g cm' % (b * 100) if b >= 0.01 else '%g mm' % (b * 1000)


def best_gpcc(rows):
    """(sequence, bound) -> the G-PCC row with the fewest bytes among those whose decoded grid
    matched the input."""
    best = {}
    for r in rows:
        if r['peer'] in GPCC and r.get('bound_held') == 'yes' and r.get('bytes') not in ('', None):
            k = (r['sequence'], r['bound_m'])
            if k not in best or int(r['bytes']) < int(best[k]['bytes']):
                best[k] = r
    return best


def _singles_total(rows):
    """Rows summed over the one-frame sequences (single/*), per bound and peer, when every
    single sequence has that peer's figures."""
    acc = {}
    names = set(r['sequence'] for r in rows if r['sequence'].startswith('single/'))
    for r in rows:
        if not r['sequence'].startswith('single/') or _f(r, 'bytes') is None:
            continue
        a = acc.setdefault((r['bound_m'], r['peer']), {'n': 0, 'bytes': 0, 'points': 0,
                                                        'err': 0.0, 'enc': 0.0, 'dec': 0.0,
                                                        'held': True})
        a['n'] += 1
        a['bytes'] += int(r['bytes'])
        a['points'] += int(r['points'])
        a['err'] = max(a['err'], _f(r, 'max_error_m'))
        a['enc'] += _f(r, 'enc_cpu_s')
        a['dec'] += _f(r, 'dec_cpu_s')
        a['held'] &= r['bound_held'] in ('yes', 'lossless')
    out = []
    for (bound, peer), a in acc.items():
        if a['n'] != len(names):
            continue
        out.append({'sequence': 'single (all 12)', 'frames': a['n'], 'points': a['points'],
                    'bound_m': bound, 'peer': peer, 'bytes': a['bytes'],
                    'bits_per_point': '%.4f' % (8.0 * a['bytes'] / a['points']),
                    'max_error_m': '%.6g' % a['err'],
                    'bound_held': ('yes' if a['held'] else 'NO') if bound != 'lossless'
                    else 'lossless',
                    'enc_Mpoints_s': '%.3f' % (a['points'] / 1e6 / max(a['enc'], 1e-9)),
                    'dec_Mpoints_s': '%.3f' % (a['points'] / 1e6 / max(a['dec'], 1e-9)),
                    'enc_cpu_s': '%.4f' % a['enc'], 'dec_cpu_s': '%.4f' % a['dec'],
                    'check': '', 'config': '', 'note': ''})
    return out


def _row(allrows, s, peer, bound='lossless'):
    """The row of sequence s, peer and bound that has a size, or None."""
    return next((r for r in allrows if r['sequence'] == s and r['peer'] == peer
                 and r['bound_m'] == bound and _f(r, 'bytes') is not None), None)


def _bpp(allrows, s, peer, bound):
    r = _row(allrows, s, peer, bound)
    return (_f(r, 'bits_per_point'), r) if r else (None, None)


def targets(seqs, allrows, best):
    """Issue #37's size targets against the strongest G-PCC and Cloudini of the same run:
    order kept at most 1.1x G-PCC and below Cloudini, --point-order any at most 0.8x, each
    within its bound; --lossless at most 0.75x xz -9e of the files."""
    lines = ['\n**Issue #37\'s targets, this run** (bits per point; the ratios are bytes over '
             'the strongest G-PCC\'s; `ok` where the target holds and the bound held)\n',
             '| sequence | bound | strongest G-PCC | its bpp | cloudini | capz (kept) | kept / '
             'G-PCC | | capz-any | any / G-PCC | |', '|---|---|---|---:|---:|---:|---:|---|---:|'
             '---:|---|']
    held = {}
    bounds = sorted(set(r['bound_m'] for r in allrows if r['bound_m'] != 'lossless'), key=float)
    for s in seqs:
        for bound in bounds:
            g = best.get((s, bound))
            if not g:
                continue
            c, _ = _bpp(allrows, s, 'cloudini', bound)
            cells = []
            for peer, limit in (('capz', 1.1), ('capz-any', 0.8)):
                v, r = _bpp(allrows, s, peer, bound)
                if v is None:
                    cells += ['', '', '']
                    continue
                x = int(r['bytes']) / int(g['bytes'])
                ok = x <= limit and r['bound_held'] == 'yes' and (
                    peer != 'capz' or c is None or v < c)
                if not s.startswith('single ('):  # the sum of the 12 rows above
                    held.setdefault((peer, bound), []).append(ok)
                cells += ['%.2f' % v, '%.2f' % x, 'ok' if ok else 'miss']
            lines.append('| %s | %s | %s | %.2f | %s | %s |' % (
                s, bound_label(bound), g['peer'], _f(g, 'bits_per_point'),
                '%.2f' % c if c is not None else '', ' | '.join(cells)))
    for s in seqs:
        xz, cl = _row(allrows, s, 'xz-9e'), _row(allrows, s, 'capz-lossless')
        if xz and cl and not s.startswith('single ('):
            held.setdefault(('capz-lossless', 'lossless'), []).append(
                int(cl['bytes']) <= 0.75 * int(xz['bytes']))
    lines.append('')
    for (peer, bound), oks in sorted(held.items()):
        lines.append('- %s%s: the target holds on %d of %d sequences' % (
            peer, '' if bound == 'lossless' else ' at ' + bound_label(bound), sum(oks),
            len(oks)))
    return lines


def markdown(rows):
    rows = list(rows)
    lines = []
    seqs = []
    for r in rows + _singles_total(rows):
        if r['sequence'] not in seqs:
            seqs.append(r['sequence'])
    allrows = rows + _singles_total(rows)
    best = best_gpcc(allrows)
    for bound in sorted(set(r['bound_m'] for r in rows if r['bound_m'] != 'lossless'),
                        key=float):
        lines.append('\n**Bits per point at %s** (geometry; `x` = this peer / the strongest '
                     'G-PCC; max error in mm in brackets; NO = bound missed)\n'
                     % bound_label(bound))
        peers = [p for p in ORDER if any(r['peer'] == p and r['bound_m'] == bound
                                          for r in allrows)]
        lines.append('| sequence | points | ' + ' | '.join(peers) + ' | strongest G-PCC |')
        lines.append('|---|---:|' + '---:|' * len(peers) + '---|')
        for s in seqs:
            cells = []
            g = best.get((s, bound))
            npts = ''
            for p in peers:
                r = next((r for r in allrows if r['sequence'] == s and r['peer'] == p
                          and r['bound_m'] == bound), None)
                if r is None:
                    cells.append('')
                    continue
                npts = r['points']
                if _f(r, 'bytes') is None:
                    cells.append('not yet' if 'not yet' in r.get('note', '') else 'failed')
                    continue
                c = '%.2f' % _f(r, 'bits_per_point')
                if g:
                    c += ' (%.2fx)' % (int(r['bytes']) / int(g['bytes']))
                c += ' [%.3f]' % (_f(r, 'max_error_m') * 1000)
                if r['bound_held'] == 'NO':
                    c += ' NO'
                cells.append(c)
            lines.append('| %s | %s | %s | %s |' % (s, npts, ' | '.join(cells),
                                                   g['peer'] if g else ''))
    lines += targets(seqs, allrows, best)
    lines.append('\n**Lossless** (bits per point over all frames; capz-lossless, xz-9e and '
                 'zstd-19 of the frame files with all their fields, xz-9e-xyz of x y z float32 '
                 'only)\n')
    lossless = [p for p in ('capz-lossless', 'xz-9e', 'zstd-19', 'xz-9e-xyz')
                if any(r['peer'] == p for r in rows)]
    lines.append('| sequence | ' + ' | '.join(lossless) + ' | 0.75x xz-9e (the `--lossless` '
                 'target) | capz-lossless / xz-9e |')
    lines.append('|---|' + '---:|' * (len(lossless) + 2))
    for s in seqs:
        cells = []
        for p in lossless:
            r = next((r for r in allrows if r['sequence'] == s and r['peer'] == p), None)
            cells.append('%.2f' % _f(r, 'bits_per_point') if r else '')
        xz, cl = _row(allrows, s, 'xz-9e'), _row(allrows, s, 'capz-lossless')
        cells.append('%.2f' % (0.75 * _f(xz, 'bits_per_point')) if xz else '')
        cells.append('%.3f' % (int(cl['bytes']) / int(xz['bytes'])) if xz and cl else '')
        lines.append('| %s | %s |' % (s, ' | '.join(cells)))
    lines.append('\n**Speed** (million points per CPU second, encode / decode, one thread)\n')
    peers = [p for p in ORDER if any(r['peer'] == p for r in allrows)]
    for bound in sorted(set(r['bound_m'] for r in rows), key=lambda b: (b == 'lossless', b)):
        ps = [p for p in peers if any(r['peer'] == p and r['bound_m'] == bound for r in allrows)]
        lines.append('\n%s:\n' % ('lossless' if bound == 'lossless' else bound_label(bound)))
        lines.append('| sequence | ' + ' | '.join(ps) + ' |')
        lines.append('|---|' + '---:|' * len(ps))
        for s in seqs:
            cells = []
            for p in ps:
                r = next((r for r in allrows if r['sequence'] == s and r['peer'] == p
                          and r['bound_m'] == bound), None)
                ok = r is not None and _f(r, 'enc_Mpoints_s') is not None
                cells.append('%.2f / %.2f' % (_f(r, 'enc_Mpoints_s'), _f(r, 'dec_Mpoints_s'))
                             if ok else '')
            lines.append('| %s | %s |' % (s, ' | '.join(cells)))
    return '\n'.join(lines) + '\n'


def plot(rows, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    allrows = list(rows) + _singles_total(rows)
    panels = [s for s in MULTI + ('single (all 12)',) if any(r['sequence'] == s for r in allrows)]
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 4.2), squeeze=False)
    style = {'gpcc-octree': ('C0', 'o-'), 'gpcc-angular': ('C1', 's-'),
             'gpcc-angular-az': ('C1', 's--'), 'gpcc-octree-inter': ('C2', '^-'),
             'gpcc-octree-angular': ('C6', 'p-'), 'gpcc-octree-angular-inter': ('C6', 'p--'),
             'cloudini': ('C3', 'v-'), 'draco': ('C4', 'D-'), 'pcl-octree': ('C5', 'x-'),
             'capz': ('k', '*-'), 'capz-any': ('k', 'P--')}
    for ax, s in zip(axes[0], panels):
        for p, (col, mk) in style.items():
            pts = sorted((_f(r, 'max_error_m') * 1000, _f(r, 'bits_per_point'))
                         for r in allrows if r['sequence'] == s and r['peer'] == p
                         and _f(r, 'bytes') is not None and r['bound_m'] != 'lossless')
            if pts:
                ax.plot([x for x, _ in pts], [y for _, y in pts], mk, color=col, label=p, ms=5)
        for p, ls in (('xz-9e-xyz', ':'),):
            r = next((r for r in allrows if r['sequence'] == s and r['peer'] == p), None)
            if r is not None:
                ax.axhline(_f(r, 'bits_per_point'), color='grey', ls=ls, lw=1,
                           label=p + ' (lossless)')
        ax.set_xscale('log')
        ax.set_yscale('log')
        ax.set_xlabel('max error on decoded points (mm)')
        ax.set_ylabel('bits per point (geometry)')
        ax.set_title(s, fontsize=10)
        ax.grid(True, which='both', alpha=0.3)
    seen = {}  # every peer of any panel, once (the single sweeps have no inter row)
    for ax in axes[0]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            seen.setdefault(lab, h)
    axes[0][-1].legend(list(seen.values()), list(seen.keys()), fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('tsv')
    ap.add_argument('--plot')
    ap.add_argument('--md')
    a = ap.parse_args()
    with open(a.tsv) as f:
        rows = list(csv.DictReader(f, delimiter='\t'))
    if a.plot:
        plot(rows, a.plot)
    text = markdown(rows)
    if a.md:
        open(a.md, 'w').write(text)
    else:
        sys.stdout.write(text)


if __name__ == '__main__':
    main()

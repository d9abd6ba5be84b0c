#!/usr/bin/env python3
"""Summarize results_sitting*.txt: per N the minimum ns/sample over the rounds of a sitting (and over all sittings)."""
import re, sys
files = sys.argv[1:]
def parse(fn):
    osd, tg, tgc, osdc, once = {}, {}, [], {}, {}
    cur = None
    for line in open(fn):
        m = re.match(r'######## (?:round \d+|once): (\S+)(?: (\S+))?', line)
        if m:
            cur = m.group(2) if m.group(1) == 'tessgen' else 'osd'
            continue
        m = re.match(r'RESULT (far L\d \S+|bfr) N (\d+) samples \d+ ns_per_sample ([\d.]+)', line)
        if m:
            osd.setdefault((m.group(1), int(m.group(2))), []).append(float(m.group(3))); continue
        m = re.match(r'RESULT (far L\d \S+) construct_stencil_ms ([\d.]+) construct_primvar_ms ([\d.]+) primvar_interp_only_ms ([\d.]+)', line)
        if m:
            d = osdc.setdefault(m.group(1), [[], [], []])
            for i in range(3): d[i].append(float(m.group(i + 2)))
            continue
        m = re.match(r'construct per deformation .*?: ([\d.]+) ms', line)
        if m and cur:
            once.setdefault(cur, {}).setdefault('construct', []).append(float(m.group(1))); continue
        m = re.match(r'\| (\d+) \| (\d+) \| ([\d.]+) \| ([\d.]+) \|(?:[^|]*\|){5}([^|]*)\|', line)
        if m and cur:
            d = once.setdefault(cur, {})
            d.setdefault(('grid', int(m.group(1))), []).append(float(m.group(4)))
            d.setdefault(('persample', int(m.group(1))), []).append(float(m.group(5)))
    return osd, osdc, once
def fmt(v): return '%.2f' % v
allosd, allc, allonce = {}, {}, {}
for fn in files:
    osd, osdc, once = parse(fn)
    for k, v in osd.items(): allosd.setdefault(k, []).extend(v)
    for k, v in osdc.items():
        d = allc.setdefault(k, [[], [], []])
        for i in range(3): d[i].extend(v[i])
    for s, d in once.items():
        for k, v in d.items(): allonce.setdefault(s, {}).setdefault(k, []).extend(v)
def table(osd, osdc, once, title):
    out = ['## ' + title, '']
    pc = once.get('pccm', {})
    out.append('| N | OSD Far L2 gregory | OSD Far L3 gregory | OSD Far L2 bspline | OSD Bfr | tessgen pccm grid | tessgen pccm per-sample | Far L2 / pccm grid | Far L2 / pccm per-sample | Bfr / pccm grid | Bfr / pccm per-sample |')
    out.append('|---|---|---|---|---|---|---|---|---|---|---|')
    for N in (9, 17, 33):
        f2 = min(osd[('far L2 gregory', N)]); f3 = min(osd[('far L3 gregory', N)])
        fb = min(osd[('far L2 bspline', N)]); b = min(osd[('bfr', N)])
        g = min(pc[('grid', N)]); p = min(pc[('persample', N)])
        out.append('| %d | %s | %s | %s | %s | %s | %s | %.1fx | %.2fx | %.1fx | %.2fx |' % (
            N, fmt(f2), fmt(f3), fmt(fb), fmt(b), fmt(g), fmt(p), f2 / g, f2 / p, b / g, b / p))
    out.append('')
    out.append('(min ns/sample; OSD: min over rounds of min-of-7 runs; tessgen: min over rounds of its min-of-5 columns)')
    out.append('')
    out.append('Construction per deformation (ms, min over rounds):')
    tc = min(pc['construct'])
    for k in ('far L2 gregory', 'far L3 gregory', 'far L2 bspline'):
        st, pr, io = (min(x) for x in osdc[k])
        out.append('  OSD %s: StencilTable::UpdateValues %.3f ms (OSD / tessgen pccm = %.3f); PrimvarRefiner+local-point stencils %.3f ms; PrimvarRefiner alone %.3f ms' % (k, st, st / tc, pr, io))
    out.append('  tessgen pccm construct per deformation: %.3f ms (rounds: %s)' % (tc, ', '.join('%.3f' % x for x in pc['construct'])))
    out.append('')
    for s in ('acc', 'gregory', 'gregory-osd'):
        if s in once:
            d = once[s]
            out.append('tessgen %s: construct %.3f ms; grid ns/sample %s; per-sample ns/sample %s' % (
                s, min(d['construct']), ' / '.join(fmt(min(d[('grid', N)])) for N in (9, 17, 33)),
                ' / '.join(fmt(min(d[('persample', N)])) for N in (9, 17, 33))))
    out.append('')
    return '\n'.join(out)
for fn in files:
    print(table(*parse(fn), title='min over the 3 rounds of ' + fn))
if len(files) > 1:
    print(table(allosd, allc, allonce, title='min over all rounds of ' + ', '.join(files)))

#!/usr/bin/env python3
"""
sectors_verify.py -- float64 verification of docs/boundaries.md sections 2-3: boundary, crease
and corner support for the quad schemes by evaluating each scheme's full-ring vertex rules on a
*virtual ring* (phantom points = affine combinations of a sector's partial ring), with the crease
limit and the crease-curve points overridden by `sector crease { }` / `sector corner { }` blocks.

Run (numpy only, about 1-3 min, mostly car):
    python3 docs/verify/sectors_verify.py                   # checks + accuracy tables
    python3 docs/verify/sectors_verify.py --json tests/data/spec/sectors_reference.json
    python3 docs/verify/sectors_verify.py --quick           # skip car and pawn

Lines are  [PASS|FAIL|INFO] name: value (tol ...).  Exit status 1 iff a check FAILs.

Inputs: ../shared/meshes/*.obj (or tests/data/meshes), ../shared/cc_limit/*.bin (or
tests/data/cc_limit).  Everything below is re-derived from the .tess files in codegen/schemes
(vertex blocks and patch blocks transcribed by hand; see VERTEX BLOCKS / PATCHES).
"""
import sys, os, math, json, struct, time
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, '..', '..'))


def find_dir(*cands):
    for c in cands:
        if os.path.isdir(c):
            return c
    return cands[0]


SHARED = os.path.normpath(os.path.join(ROOT, '..', 'shared'))
MESH_DIR = find_dir(os.path.join(ROOT, 'tests', 'data', 'meshes'), os.path.join(SHARED, 'meshes'))
GT_DIRS = [os.path.join(ROOT, 'tests', 'data', 'cc_limit'), os.path.join(SHARED, 'cc_limit')]
INF = 10.0

FAILS, ROWS = [], []


def report(name, value, tol=None, kind='le'):
    if kind == 'info' or tol is None:
        tag = 'INFO'
    else:
        ok = bool(value <= tol)
        tag = 'PASS' if ok else 'FAIL'
        if not ok:
            FAILS.append(name)
    tol_s = '' if tol is None else '  (tol %.1e)' % tol
    vs = ('%.3e' % value) if isinstance(value, (float, np.floating)) else str(value)
    line = '[%s] %s: %s%s' % (tag, name, vs, tol_s)
    ROWS.append(line)
    print(line, flush=True)


def angles_deg(a, b):
    c = np.cross(a, b)
    return np.degrees(np.arctan2(np.linalg.norm(c, axis=-1), np.einsum('...k,...k->...', a, b)))

# ---------------------------------------------------------------------------------------------
# VERTEX BLOCKS (codegen/schemes/*.tess, transcribed).  P: array (2n+1, d) = [p, p_0 .. p_{2n-1}]
# (d = 3 for points, d = number of partial-ring slots for stencil rows: the blocks are linear).
# `hook(name, value)` returns the value after sector overrides; later definitions see it.
# Per-position outputs are lists over j = 0..n-1 (indices mod n).
# ---------------------------------------------------------------------------------------------

def _ring(P, n):
    p = P[0]
    q = lambda k: P[1 + (2 * k) % (2 * n)]
    d = lambda k: P[1 + (2 * k + 1) % (2 * n)]
    return p, q, d


def _limit(P, n):
    p, q, d = _ring(P, n)
    return (n * n * p + 4 * sum(q(k) for k in range(n)) + sum(d(k) for k in range(n))) / (n * (n + 5))


def _tangent(P, n):
    p, q, d = _ring(P, n)
    cp = math.cos(math.pi / n); sg = 1 / math.sqrt(4 + cp * cp)
    return [sum((1 + cp * sg) / n * math.cos(2 * math.pi * (k - j) / n) * q(k)
                + sg / n * math.cos((2 * (k - j) + 1) * math.pi / n) * d(k) for k in range(n)) for j in range(n)]


def _r(P, n):
    p, q, d = _ring(P, n)
    return [(q(j + 1) - q(j - 1)) / 3 + (d(j) - d(j - 1)) / 6 for j in range(n)]


def vb_regular(P, n, hook):
    p, q, d = _ring(P, n)
    f = hook('f', [(4 * p + 2 * q(j) + 2 * q(j + 1) + d(j)) / 9 for j in range(n)])
    e = hook('e', [(f[j - 1] + f[j]) / 2 for j in range(n)])
    v = hook('v', _limit(P, n))
    return dict(f=f, e=e, v=v)


def vb_acc(P, n, hook):
    p, q, d = _ring(P, n)
    f = hook('f', [(n * p + 2 * q(j) + 2 * q(j + 1) + d(j)) / (n + 5) for j in range(n)])
    e = hook('e', [(f[j - 1] + f[j]) / 2 for j in range(n)])
    v = hook('v', _limit(P, n))
    t = hook('t', _tangent(P, n))
    return dict(f=f, e=e, v=v, t=t)


def vb_gregory(P, n, hook):
    p, q, d = _ring(P, n)
    f = hook('f', [(4 * p + 2 * q(j) + 2 * q(j + 1) + d(j)) / 9 for j in range(n)])
    v = hook('v', _limit(P, n))
    t = hook('t', _tangent(P, n))                       # let
    e = hook('e', [v + t[j] / 3 for j in range(n)])
    r = hook('r', _r(P, n))
    return dict(f=f, v=v, t=t, e=e, r=r)


def vb_gregory_osd(P, n, hook):
    p, q, d = _ring(P, n)
    c = math.cos(2 * math.pi / n)
    lam = (5 + c + math.cos(math.pi / n) * math.sqrt(18 + 2 * c)) / 16
    f = hook('f', [(4 * p + 2 * q(j) + 2 * q(j + 1) + d(j)) / 9 for j in range(n)])
    v = hook('v', _limit(P, n))
    fa = hook('fa', [(n * p + 2 * q(j) + 2 * q(j + 1) + d(j)) / (n + 5) for j in range(n)])   # let
    ea = hook('ea', [(fa[j - 1] + fa[j]) / 2 for j in range(n)])                              # let
    e = hook('e', [v + sum(math.cos(2 * math.pi * (k - j) / n) * ea[k] for k in range(n)) / (n * lam)
                   for j in range(n)])
    r = hook('r', _r(P, n))
    return dict(f=f, v=v, fa=fa, ea=ea, e=e, r=r)


def vb_pccm(P, n, hook):
    p, q, d = _ring(P, n)
    c = math.cos(2 * math.pi / n)
    sigma = (c + 5 + math.sqrt((c + 9) * (c + 1))) / 16
    f = hook('f', [(4 * p + 2 * q(j) + 2 * q(j + 1) + d(j)) / 9 for j in range(n)])
    e = hook('e', [(f[j - 1] + f[j]) / 2 for j in range(n)])
    v = hook('v', _limit(P, n))
    if n == 4:
        t = list(e)
    else:
        t = [v + 4 * sigma / n * sum(math.cos(2 * math.pi * (k - j) / n) * e[k] for k in range(n)) for j in range(n)]
    t = hook('t', t)
    return dict(f=f, e=e, v=v, t=t)


# exported outputs in declaration order (not `let`), and whether each is a vector
SCHEMES = {
    'regular': (vb_regular, [('f', 0), ('e', 0), ('v', 0)]),
    'acc': (vb_acc, [('f', 0), ('e', 0), ('v', 0), ('t', 1)]),
    'gregory': (vb_gregory, [('f', 0), ('v', 0), ('e', 0), ('r', 1)]),
    'gregory_osd': (vb_gregory_osd, [('f', 0), ('v', 0), ('e', 0), ('r', 1)]),
    'pccm': (vb_pccm, [('f', 0), ('e', 0), ('v', 0), ('t', 0)]),
}
PER_POS = {'f', 'e', 't', 'r', 'fa', 'ea'}

# ---------------------------------------------------------------------------------------------
# SECTOR BLOCKS: overrides.  Each entry: name -> (sharp_only, fn(P, m, j)) with P the virtual
# ring [p, p_0 ..] (slot p[i] = P[1 + i]).  The DSL text is printed by --print-overrides.
# ---------------------------------------------------------------------------------------------

def ov_crease_v(P, m, j):
    return (P[1] + 4 * P[0] + P[1 + 2 * m]) / 6


def ov_corner_v(P, m, j):
    return P[0]


def ov_sharp_e(P, m, j):
    return (2 * P[0] + P[1 + 2 * j]) / 3


def ov_acc_t_crease(P, m, j):
    return (P[1 + 2 * j] - P[1 + 2 * m - 2 * j]) / 2


def ov_acc_t_corner(P, m, j):
    return P[1 + 2 * j] - P[0]


def ov_zero(P, m, j):
    return 0 * P[0]



def _t_exact(P, m, j):
    """cos(pi j/m) T_along + sin(pi j/m) T_across, T_across = boundary.md 3.3 exact mask (its scale)."""
    X = exact_across_mask(m)
    Tx = sum(X[k] * P[k] for k in range(2 * m + 2))       # partial-ring slots = virtual slots 0..2m+1
    Ta = (P[1] - P[1 + 2 * m]) / 2
    return math.cos(math.pi * j / m) * Ta + math.sin(math.pi * j / m) * Tx


def ov_t_exact_vec(P, m, j):
    return _t_exact(P, m, j)


def ov_t_exact_point(P, m, j):          # pccm t / gregory_osd e: a point v + T/3
    return ov_crease_v(P, m, j) + _t_exact(P, m, j) / 3


DSL = {}


# The adopted sector blocks (codegen/schemes/*.tess) override the crease tangents with the exact
# masks for m >= 3 ('exact'); `--virtual-ring-tangents` makes the previous construction (every
# tangent from the virtual ring, 'virtual') the default of every table and of --json.
PROPOSED = 'virtual' if '--virtual-ring-tangents' in sys.argv else 'exact'


def overrides(scheme, kind, variant='proposed', m=None):
    """the sector block of `scheme` for `kind` ('crease'|'corner').  variant 'doc' = the typical
    block of docs/boundaries.md section 3 (v + sharp e) for every scheme; 'virtual' = v, sharp e and
    acc/pccm sharp t (tangents from the virtual ring); 'exact' = 'virtual' plus the exact crease
    tangents for m >= 3 (the .tess files); 'proposed' = PROPOSED; 'r0' = PROPOSED plus Gregory's
    sharp r = 0."""
    if variant == 'proposed':
        variant = PROPOSED
    o = {'v': (False, ov_crease_v if kind == 'crease' else ov_corner_v), 'e': (True, ov_sharp_e)}
    if variant == 'doc':
        return o
    if scheme == 'acc':
        o['t'] = (True, ov_acc_t_crease if kind == 'crease' else ov_acc_t_corner)
    if scheme == 'pccm':
        o['t'] = (True, ov_sharp_e)
    exact = variant == 'exact' or (variant == 'r0' and PROPOSED == 'exact')
    # m = 2: the virtual ring is exact (the exact mask equals it up to rounding), m = 1: corner.
    # At the sharp positions the exact tangents equal the sharp overrides (which the .tess keeps).
    if exact and kind == 'crease' and m is not None and m >= 3:
        if scheme in ('acc', 'gregory'):
            o['t'] = (False, ov_t_exact_vec)
        elif scheme == 'pccm':
            o['t'] = (False, ov_t_exact_point)
        elif scheme == 'gregory_osd':
            o['e'] = (False, ov_t_exact_point)
    if variant == 'r0' and scheme in ('gregory', 'gregory_osd'):
        o['r'] = (True, ov_zero)
    return o


DSL_LINES = {
    ('*', 'crease', 'v'): 'v = (p[0] + 4 * p + p[2 * m]) / 6;',
    ('*', 'corner', 'v'): 'v = p;',
    ('*', '*', 'e'): 'sharp e[j] = (2 * p + p[2 * j]) / 3;',
    ('acc', 'crease', 't'): 'sharp t[j] = (p[2 * j] - p[2 * m - 2 * j]) / 2;',
    ('acc', 'corner', 't'): 'sharp t[j] = p[2 * j] - p;',
    ('pccm', '*', 't'): 'sharp t[j] = (2 * p + p[2 * j]) / 3;',
}

# ---------------------------------------------------------------------------------------------
# virtual ring (docs/boundaries.md section 3): matrix Phi (2n'+1) x (2m+2) over the partial ring
# [p, q_0, d_0, ..., d_{m-1}, q_m]  (p = 0, q_i = 1 + 2i, d_i = 2 + 2i)
# ---------------------------------------------------------------------------------------------

def virtual_valence(m):
    return 4 if m == 1 else 2 * m


def virtual_ring(m):
    K = 2 * m + 2
    n = virtual_valence(m)
    e = np.eye(K)
    P, Q, D = e[0], (lambda i: e[1 + 2 * i]), (lambda i: e[2 + 2 * i])
    slots = [None] * (2 * n)
    for i in range(m + 1):
        slots[2 * i] = Q(i)
    for i in range(m):
        slots[2 * i + 1] = D(i)
    if m == 1:
        slots[3] = 2 * Q(1) - D(0)                           # D_1
        slots[4] = 2 * P - Q(0)                              # Q_2
        slots[5] = 4 * P - 2 * Q(0) - 2 * Q(1) + D(0)        # D_2
        slots[6] = 2 * P - Q(1)                              # Q_3
        slots[7] = 2 * Q(0) - D(0)                           # D_3
    else:
        for i in range(1, m):
            slots[2 * (m + i)] = 2 * P - Q(i)                # Q_{m+i}
        slots[2 * m + 1] = 2 * Q(m) - D(m - 1)               # D_m
        slots[2 * (2 * m - 1) + 1] = 2 * Q(0) - D(0)         # D_{2m-1}
        for i in range(1, m - 1):
            slots[2 * (m + i) + 1] = 2 * P - D(i)            # D_{m+i}
    assert all(s is not None for s in slots)
    return np.array([P] + slots)


def run_block(scheme, P, n, ovr=None, m=None):
    fn = SCHEMES[scheme][0]

    def hook(name, val):
        if not ovr or name not in ovr:
            return val
        sharp, g = ovr[name]
        if name not in PER_POS:
            return g(P, m, None)
        val = list(val)
        for j in range(n):
            if (not sharp) or j == 0 or j == m:
                val[j] = g(P, m, j)
        return val
    return fn(P, n, hook)


_SECTOR_CACHE = {}


def sector_rows(scheme, kind, m, variant='proposed'):
    """dict name -> per-position array (m+1, 2m+2) or single (2m+2,) over the partial ring."""
    key = (scheme, kind, m, variant)
    if key not in _SECTOR_CACHE:
        Phi = virtual_ring(m)
        n = virtual_valence(m)
        out = run_block(scheme, Phi, n, overrides(scheme, kind, variant, m), m)
        rows = {}
        for name, val in out.items():
            rows[name] = np.array(val[:m + 1]) if name in PER_POS else np.array(val)
        _SECTOR_CACHE[key] = rows
    return _SECTOR_CACHE[key]


_FULL_CACHE = {}


def full_rows(scheme, n):
    if (scheme, n) not in _FULL_CACHE:
        out = run_block(scheme, np.eye(2 * n + 1), n)
        _FULL_CACHE[(scheme, n)] = {k: (np.array(v) if k in PER_POS else np.array(v)) for k, v in out.items()}
    return _FULL_CACHE[(scheme, n)]

# ---------------------------------------------------------------------------------------------
# mesh input, tags, sectors (docs/boundaries.md section 2)
# ---------------------------------------------------------------------------------------------

def load_obj(name):
    V, F, crease, corner, ib = [], [], {}, {}, None
    for line in open(os.path.join(MESH_DIR, name + '.obj')):
        t = line.split()
        if not t:
            continue
        if t[0] == 'v':
            V.append([float(x) for x in t[1:4]])
        elif t[0] == 'f':
            F.append([int(x.split('/')[0]) - 1 for x in t[1:]])
        elif t[0] == 't':
            ni, nf, ns = map(int, t[2].split('/'))
            ints = list(map(int, t[3:3 + ni])); fl = list(map(float, t[3 + ni:3 + ni + nf]))
            if t[1] == 'crease':
                if nf > 1:
                    pairs = [(ints[2 * j], ints[2 * j + 1], fl[j]) for j in range(ni // 2)]
                else:
                    pairs = [(ints[j], ints[j + 1], fl[0]) for j in range(ni - 1)]
                for a, b, s in pairs:
                    crease[frozenset((a, b))] = s
            elif t[1] == 'corner':
                for j, v in enumerate(ints):
                    corner[v] = fl[j] if nf > 1 else fl[0]
            elif t[1] == 'interpolateboundary':
                ib = ints[0]
    return np.array(V), F, crease, corner, (1 if ib is None else ib)


def load_gt(fname):
    for d in GT_DIRS:
        path = os.path.join(d, fname)
        if os.path.exists(path):
            b = open(path, 'rb').read()
            assert b[:8] == b'CCLIM001'
            Fn, n, k, flags, nv, _ = struct.unpack('<6I', b[8:32])
            return np.frombuffer(b, '<f4', offset=32).reshape(Fn, n, n, k).astype(np.float64)
    raise FileNotFoundError(fname)


class Mesh:
    """treatment: 'sharp' = semi-sharp creases (0 < s < 10) approximated as infinitely sharp
    (docs/boundaries.md section 1); 'smooth' = semi-sharp creases ignored (s >= 10 kept);
    'none' = all crease / corner tags ignored (compare with .smooth.bin)."""

    def __init__(self, name, treatment='sharp'):
        self.name = name
        self.V, self.F, self.crease, self.cornertag, self.ib = load_obj(name)
        self.treatment = treatment
        self.he = {}
        for f, fv in enumerate(self.F):
            assert len(fv) == 4
            for i in range(4):
                self.he[(fv[i], fv[(i + 1) % 4])] = (f, i)
        self.vfaces = [[] for _ in self.V]
        for f, fv in enumerate(self.F):
            for v in fv:
                self.vfaces[v].append(f)
        self.h = np.array([np.mean([np.linalg.norm(self.V[fv[i]] - self.V[fv[(i + 1) % 4]])
                                    for i in range(4)]) for fv in self.F])
        self.info = {}
        for x in range(len(self.V)):
            if self.vfaces[x]:
                self.info[x] = self.vertex_info(x)

    def sharpness(self, a, b):
        s = self.crease.get(frozenset((a, b)), 0.0)
        if self.treatment == 'none' or (self.treatment == 'smooth' and s < INF):
            return 0.0
        return s

    def is_boundary(self, a, b):
        return ((a, b) in self.he) != ((b, a) in self.he)

    def sharp(self, a, b):
        return (self.is_boundary(a, b) and self.ib != 0) or self.sharpness(a, b) > 0

    def semi(self, a, b):
        s = self.crease.get(frozenset((a, b)), 0.0)
        return 0.0 < s < INF and not self.is_boundary(a, b)

    def vertex_info(self, x):
        """ring positions, rule and sectors of vertex x (docs/boundaries.md section 2)."""
        outs = []       # (half-edge id, face, q, d, y)
        for f in self.vfaces[x]:
            i = self.F[f].index(x)
            r = [self.F[f][(i + k) % 4] for k in range(4)]
            outs.append((4 * f + i, f, r[1], r[2], r[3]))
        by_q = {o[2]: o for o in outs}
        lead = [o for o in outs if (o[2], x) not in self.he]          # p -> q_0 has no twin
        boundary = bool(lead)
        sharpq = lambda q: self.sharp(x, q)
        nsharp_edges = set(o[2] for o in outs if sharpq(o[2])) | set(o[4] for o in outs if sharpq(o[4]))
        s = len(nsharp_edges)
        nf = len(outs)
        vs = 0.0 if self.treatment == 'none' else self.cornertag.get(x, 0.0)
        if vs > 0 or s >= 3 or (self.ib == 1 and boundary and nf == 1):
            rule = 'corner'
        elif s == 2:
            rule = 'crease'
        elif s == 1:
            rule = 'dart'
        else:
            rule = 'smooth'
        if boundary:
            assert len(lead) == 1, 'non-manifold vertex %d' % x
            start = lead[0]
        elif rule in ('crease', 'corner') and s > 0:
            start = min(o for o in outs if sharpq(o[2]))
        else:
            start = min(outs)
        seq, o = [], start
        while True:
            seq.append(o)
            nxt = by_q.get(o[4])
            if nxt is None or nxt is start:
                break
            o = nxt
        assert len(seq) == nf
        q = [o[2] for o in seq] + ([seq[-1][4]] if boundary else [])
        nl = len(q)
        info = dict(rule=rule, boundary=boundary, faces=[o[1] for o in seq], q=q, d=[o[3] for o in seq],
                    n_layout=nl, nsharp=s,
                    semi=any(self.semi(x, qq) for qq in q),
                    semi_s=max([self.crease.get(frozenset((x, qq)), 0.0) for qq in q
                                if self.semi(x, qq)] or [0.0]))
        info['pos_of_face'] = {o[1]: j for j, o in enumerate(seq)}
        if rule in ('smooth', 'dart'):
            info['ring'] = [x] + [v for o in seq for v in (o[2], o[3])]
            return info
        # sectors: cut at sharp positions
        sharp_pos = [j for j in range(nf) if sharpq(q[j])]
        if not sharp_pos:                       # t corner on a smooth vertex: one sector, q_m = q_0
            sharp_pos = [0]
        sectors = []
        for k, j0 in enumerate(sharp_pos):
            j1 = sharp_pos[k + 1] if k + 1 < len(sharp_pos) else (nf if boundary else nf + sharp_pos[0])
            m = j1 - j0
            ring = [x]
            for j in range(j0, j1):
                ring += [q[j % nl], seq[j % nf][3]]
            ring.append(q[j1 % nl])
            last = (k == len(sharp_pos) - 1)
            count = m + 1 if (boundary and last) else m
            sectors.append(dict(j0=j0, m=m, ring=ring, count=count,
                                kind=0 if rule == 'crease' else 1))
        if boundary:
            assert sharp_pos[0] == 0
        info['sectors'] = sectors
        return info

    def sector_of(self, x, f):
        """(sector index, local position) of face f in the sectors of x."""
        c = self.info[x]
        j = c['pos_of_face'][f]
        for k, sec in enumerate(c['sectors']):
            jl = (j - sec['j0']) % c['n_layout']
            if jl < sec['m']:
                return k, jl
        raise AssertionError('face %d not in a sector of %d' % (f, x))

    def corner_regular(self, x, f):
        c = self.info[x]
        if c['rule'] == 'smooth':
            return c['n_layout'] == 4 and not c['boundary']
        if c['rule'] == 'dart':
            return False
        k, _ = self.sector_of(x, f)
        return c['sectors'][k]['m'] == (2 if c['rule'] == 'crease' else 1)

    def face_touches_semi(self, f):
        return max(self.info[x]['semi_s'] for x in self.F[f])

# ---------------------------------------------------------------------------------------------
# vertex stage on a mesh: per vertex, per position: the scheme's outputs
# ---------------------------------------------------------------------------------------------

class VertexStage:
    """layout 'sector': every face reads its own sector's outputs at j and j+1 (ideal);
    'doc': the flat layout of docs/boundaries.md section 2/4 (every ring position written once;
    an interior sector's position j0 + m is written by the next sector as its j = 0)."""

    def __init__(self, mesh, scheme, variant='proposed', layout='sector'):
        self.m, self.s, self.variant, self.layout = mesh, scheme, variant, layout
        self.cache = {}

    def vertex(self, x):
        if x in self.cache:
            return self.cache[x]
        me, c = self.m, self.m.info[x]
        X = me.V
        if 'ring' in c:
            n = c['n_layout']
            R = full_rows(self.s, n)
            Y = X[c['ring']]
            out = dict(kind='full', n=n, vals={k: (np.einsum('jk,kd->jd', np.array(v), Y) if k in PER_POS else v @ Y)
                                               for k, v in R.items()})
        else:
            secs = []
            for sec in c['sectors']:
                R = sector_rows(self.s, 'crease' if sec['kind'] == 0 else 'corner', sec['m'], self.variant)
                Y = X[sec['ring']]
                secs.append(dict(sec, n=virtual_valence(sec['m']),
                                 vals={k: (v @ Y) for k, v in R.items()}))
            out = dict(kind='sectors', secs=secs, nl=c['n_layout'], boundary=c['boundary'])
        self.cache[x] = out
        return out

    def corner(self, f, i):
        """corner data of face f, corner i: n (for the per-valence constants) and the outputs
        v, e0 = e(i,0), e1 = e(i,1), f0, t0, t1, r0, r1."""
        me = self.m
        x = me.F[f][i]
        c = me.info[x]
        j = c['pos_of_face'][f]
        vs = self.vertex(x)
        d = {}
        if vs['kind'] == 'full':
            n = vs['n']; V = vs['vals']
            d['n'] = n
            for name, val in V.items():
                if name in PER_POS:
                    d[name + '0'] = val[j % n]; d[name + '1'] = val[(j + 1) % n]
                else:
                    d[name] = val
            return d
        secs = vs['secs']
        k, jl = me.sector_of(x, f)
        sec = secs[k]
        V = sec['vals']
        d['n'] = sec['n']
        for name, val in V.items():
            if name in PER_POS:
                d[name + '0'] = val[jl]
                if self.layout == 'doc' and jl + 1 == sec['m'] and sec['count'] == sec['m']:
                    nxt = secs[(k + 1) % len(secs)]
                    d[name + '1'] = nxt['vals'][name][0]
                else:
                    d[name + '1'] = val[jl + 1]
            else:
                d[name] = V['v'] if name == 'v' else val
        # single outputs are written only by the sector with j0 = 0
        d['v'] = secs[0]['vals']['v']
        return d

# ---------------------------------------------------------------------------------------------
# PATCHES (patch blocks of the .tess files) and their evaluation on the 9x9 grid.
# All patches are linear in their control points for fixed (u, v): basis matrices are built once
# by evaluating with unit control points.
# ---------------------------------------------------------------------------------------------

T9 = np.linspace(0, 1, 9)


def bern(n, t):
    return np.array([math.comb(n, i) * t ** i * (1 - t) ** (n - i) for i in range(n + 1)])


def dbern(n, t):
    b = bern(n - 1, t); d = np.zeros(n + 1)
    for i in range(n + 1):
        if i >= 1: d[i] += n * b[i - 1]
        if i <= n - 1: d[i] -= n * b[i]
    return d


CORNER_SAMPLES = [(0, 0), (0, 8), (8, 0), (8, 8)]          # (j, i) sample indices of the face corners
EPS_CORNER = 1e-6                                          # as cc_limit/README.md, degenerate corners


def _grid_basis(fn, ncontrol):
    """fn(C (ncontrol, ncontrol), u, v) -> (P, Pu, Pv) each (ncontrol,); returns (3, 85, ncontrol):
    81 samples in order [j][i] (v-index major) like the .bin files, then the 4 face corners moved
    by 1e-6 diagonally into the face (used where the corner normal is degenerate)."""
    E = np.eye(ncontrol)
    B = np.zeros((3, 85, ncontrol))
    pts = [(T9[ii], T9[jj]) for jj in range(9) for ii in range(9)]
    for jj, ii in CORNER_SAMPLES:
        pts.append((abs(T9[ii] - EPS_CORNER), abs(T9[jj] - EPS_CORNER)))
    for r, (u, v) in enumerate(pts):
        out = fn(E, u, v)
        for k in range(3):
            B[k, r] = out[k]
    return B


def bicubic_eval(C, u, v):          # C: (16, d) row 4*i + j (i along u)
    G = C.reshape(4, 4, -1)
    Bu, Bv, Du, Dv = bern(3, u), bern(3, v), dbern(3, u), dbern(3, v)
    return (np.einsum('i,j,ijk->k', Bu, Bv, G), np.einsum('i,j,ijk->k', Du, Bv, G),
            np.einsum('i,j,ijk->k', Bu, Dv, G))


def acc_tan_eval(C, u, v):          # C: (24, d): U (3x4, row 4a+j) then V (4x3, row 3i+b)
    U = C[:12].reshape(3, 4, -1); V = C[12:].reshape(4, 3, -1)
    Tu = np.einsum('i,j,ijk->k', bern(2, u), bern(3, v), U)
    Tv = np.einsum('i,j,ijk->k', bern(3, u), bern(2, v), V)
    return Tu, Tv, 0 * Tu


def gregory_eval(C, u, v):          # C: (20, d) corner k rows 5k..5k+4 = P, E+, E-, F+, F-
    G = lambda k, r: C[5 * k + r]
    ctrl = np.zeros((4, 4) + C.shape[1:]); cu = np.zeros_like(ctrl); cv = np.zeros_like(ctrl)
    ctrl[0, 0], ctrl[1, 0], ctrl[0, 1] = G(0, 0), G(0, 1), G(0, 2)
    ctrl[3, 0], ctrl[3, 1], ctrl[2, 0] = G(1, 0), G(1, 1), G(1, 2)
    ctrl[3, 3], ctrl[2, 3], ctrl[3, 2] = G(2, 0), G(2, 1), G(2, 2)
    ctrl[0, 3], ctrl[0, 2], ctrl[1, 3] = G(3, 0), G(3, 1), G(3, 2)

    def blend(Fa, wa, dwa, Fb, wb, dwb):
        s = wa + wb
        if s <= 0:
            return 0.5 * (Fa + Fb), 0 * Fa, 0 * Fa
        X = (wa * Fa + wb * Fb) / s
        d = [((dwa[t] * Fa + dwb[t] * Fb) * s - (wa * Fa + wb * Fb) * (dwa[t] + dwb[t])) / s ** 2 for t in range(2)]
        return X, d[0], d[1]
    F = lambda k, pm: G(k, 3 if pm else 4)
    inter = {(1, 1): blend(F(0, 1), u, (1, 0), F(0, 0), v, (0, 1)),
             (2, 1): blend(F(1, 1), v, (0, 1), F(1, 0), 1 - u, (-1, 0)),
             (2, 2): blend(F(2, 1), 1 - u, (-1, 0), F(2, 0), 1 - v, (0, -1)),
             (1, 2): blend(F(3, 1), 1 - v, (0, -1), F(3, 0), u, (1, 0))}
    for (i, j), (X, du, dv) in inter.items():
        ctrl[i, j] = X; cu[i, j] = du; cv[i, j] = dv
    Bu, Bv, Du, Dv = bern(3, u), bern(3, v), dbern(3, u), dbern(3, v)
    P = np.einsum('i,j,ijk->k', Bu, Bv, ctrl)
    Pu = np.einsum('i,j,ijk->k', Du, Bv, ctrl) + np.einsum('i,j,ijk->k', Bu, Bv, cu)
    Pv = np.einsum('i,j,ijk->k', Bu, Dv, ctrl) + np.einsum('i,j,ijk->k', Bu, Bv, cv)
    return P, Pu, Pv


PIECE_BARY = {
    0: (np.array([1.0, 0.0, 0.0]), np.array([-1.0, 1.0, 0.0]), np.array([-1.0, -1.0, 2.0])),
    1: (np.array([0.0, -1.0, 2.0]), np.array([1.0, 1.0, -2.0]), np.array([-1.0, 1.0, 0.0])),
    2: (np.array([-1.0, 0.0, 2.0]), np.array([1.0, -1.0, 0.0]), np.array([1.0, 1.0, -2.0])),
    3: (np.array([0.0, 1.0, 0.0]), np.array([-1.0, -1.0, 2.0]), np.array([1.0, -1.0, 0.0])),
}


def piece_of(u, v):
    if v <= u and u + v <= 1: return 0
    if u >= v and u + v >= 1: return 1
    if v >= u and u + v >= 1: return 2
    return 3


def cpatch_eval(C, u, v):
    """C: (24, d) c-coefficients, row 6i + k, k: v, t0, t1, b211, b121, b112 (pccm.md section 4)."""
    g = lambda i, k: C[6 * (i % 4) + k]
    v_, t0, t1, P_, Q_, B_ = [[g(i, k) for i in range(4)] for k in range(6)]
    b310 = [(v_[i] + 3 * t0[i]) / 4 for i in range(4)]
    b130 = [(v_[(i + 1) % 4] + 3 * t1[(i + 1) % 4]) / 4 for i in range(4)]
    centre = (B_[0] + B_[1] + B_[2] + B_[3]) / 4
    i = piece_of(u, v); im, ip = (i - 1) % 4, (i + 1) % 4
    N = {(4, 0, 0): v_[i], (3, 1, 0): b310[i], (2, 2, 0): (t0[i] + t1[ip]) / 2, (1, 3, 0): b130[i],
         (0, 4, 0): v_[ip], (2, 1, 1): P_[i], (1, 2, 1): Q_[i], (1, 1, 2): B_[i],
         (3, 0, 1): (b310[i] + b130[im]) / 2, (0, 3, 1): (b130[i] + b310[ip]) / 2,
         (2, 0, 2): (P_[i] + Q_[im]) / 2, (0, 2, 2): (Q_[i] + P_[ip]) / 2,
         (1, 0, 3): (B_[i] + B_[im]) / 2, (0, 1, 3): (B_[i] + B_[ip]) / 2, (0, 0, 4): centre}
    a, bu, bv = PIECE_BARY[i]
    lam = a + bu * u + bv * v
    cur, deg = N, 4
    while deg > 1:
        nxt = {}
        for k in range(deg):
            for l in range(deg - k):
                mm = deg - 1 - k - l
                nxt[(k, l, mm)] = lam[0] * cur[(k + 1, l, mm)] + lam[1] * cur[(k, l + 1, mm)] + lam[2] * cur[(k, l, mm + 1)]
        cur, deg = nxt, deg - 1
    P = [cur[(1, 0, 0)], cur[(0, 1, 0)], cur[(0, 0, 1)]]
    pos = lam[0] * P[0] + lam[1] * P[1] + lam[2] * P[2]
    return pos, 4 * (bu[0] * P[0] + bu[1] * P[1] + bu[2] * P[2]), 4 * (bv[0] * P[0] + bv[1] * P[1] + bv[2] * P[2])


BASIS = {}


def basis():
    if not BASIS:
        BASIS['bicubic'] = _grid_basis(bicubic_eval, 16)
        BASIS['acc_tan'] = _grid_basis(acc_tan_eval, 24)
        BASIS['gregory'] = _grid_basis(gregory_eval, 20)
        BASIS['cpatch'] = _grid_basis(cpatch_eval, 24)
    return BASIS


def cs(n):
    exact = {3: (-0.5, math.sqrt(3.0) / 2), 4: (0.0, 1.0), 6: (0.5, math.sqrt(3.0) / 2)}
    return exact.get(n, (math.cos(2 * math.pi / n), math.sin(2 * math.pi / n)))


def bicubic_ctrl(C):
    G = np.zeros((4, 4, 3))
    G[0, 0], G[1, 0], G[0, 1], G[1, 1] = C[0]['v'], C[0]['e0'], C[0]['e1'], C[0]['f0']
    G[3, 0], G[3, 1], G[2, 0], G[2, 1] = C[1]['v'], C[1]['e0'], C[1]['e1'], C[1]['f0']
    G[3, 3], G[2, 3], G[3, 2], G[2, 2] = C[2]['v'], C[2]['e0'], C[2]['e1'], C[2]['f0']
    G[0, 3], G[0, 2], G[1, 3], G[1, 2] = C[3]['v'], C[3]['e0'], C[3]['e1'], C[3]['f0']
    return G.reshape(16, 3)


def acc_tangent_ctrl(C, G16):
    """acc.tess `patch extraordinary: acc` in the (u, v) frame (= schemes_verify.stencil_acc_tangents)."""
    b = lambda i, j: G16[4 * i + j]
    c = [cs(C[k]['n'])[0] for k in range(4)]
    T = []
    for k in range(4):
        t0, t1 = C[k]['t0'], C[k]['t1']
        T.append([(t0, t1), (-t1, t0), (-t0, -t1), (t1, -t0)][k])
    U = np.zeros((12, 3)); V = np.zeros((12, 3))
    Ui = lambda a, j: 4 * a + j
    Vi = lambda i, bb: 3 * i + bb
    U[Ui(0, 0)], V[Vi(0, 0)] = T[0]
    U[Ui(2, 0)], V[Vi(3, 0)] = T[1]
    U[Ui(2, 3)], V[Vi(3, 2)] = T[2]
    U[Ui(0, 3)], V[Vi(0, 2)] = T[3]
    for j in range(4):
        U[Ui(1, j)] = 3 * (b(2, j) - b(1, j))
    for i in range(4):
        V[Vi(i, 1)] = 3 * (b(i, 2) - b(i, 1))
    t0, t1, t2 = V[Vi(0, 0)], V[Vi(0, 1)], V[Vi(0, 2)]
    U[Ui(0, 1)] = 3 * (b(1, 1) - b(0, 1)) + (2 * c[0] * t1 - c[3] * t0) / 3
    U[Ui(0, 2)] = 3 * (b(1, 2) - b(0, 2)) + (c[0] * t2 - 2 * c[3] * t1) / 3
    t0, t1, t2 = V[Vi(3, 0)], V[Vi(3, 1)], V[Vi(3, 2)]
    U[Ui(2, 1)] = 3 * (b(3, 1) - b(2, 1)) - (2 * c[1] * t1 - c[2] * t0) / 3
    U[Ui(2, 2)] = 3 * (b(3, 2) - b(2, 2)) - (c[1] * t2 - 2 * c[2] * t1) / 3
    t0, t1, t2 = U[Ui(0, 0)], U[Ui(1, 0)], U[Ui(2, 0)]
    V[Vi(1, 0)] = 3 * (b(1, 1) - b(1, 0)) + (2 * c[0] * t1 - c[1] * t0) / 3
    V[Vi(2, 0)] = 3 * (b(2, 1) - b(2, 0)) + (c[0] * t2 - 2 * c[1] * t1) / 3
    t0, t1, t2 = U[Ui(0, 3)], U[Ui(1, 3)], U[Ui(2, 3)]
    V[Vi(1, 2)] = 3 * (b(1, 3) - b(1, 2)) - (2 * c[3] * t1 - c[2] * t0) / 3
    V[Vi(2, 2)] = 3 * (b(2, 3) - b(2, 2)) - (c[3] * t2 - 2 * c[2] * t1) / 3
    return np.vstack([U, V])


def gregory_ctrl(C):
    c = [cs(C[k]['n'])[0] for k in range(4)]
    W = np.zeros((20, 3))
    for i in range(4):
        ip, im = (i + 1) % 4, (i - 1) % 4
        fp = (c[ip] * C[i]['v'] + (3 - 2 * c[i] - c[ip]) * C[i]['e0'] + 2 * c[i] * C[ip]['e1'] + C[i]['r0']) / 3
        fm = (c[im] * C[i]['v'] + (3 - 2 * c[i] - c[im]) * C[i]['e1'] + 2 * c[i] * C[im]['e0'] - C[i]['r1']) / 3
        W[5 * i:5 * i + 5] = [C[i]['v'], C[i]['e0'], C[i]['e1'], fp, fm]
    return W


def cpatch_ctrl(C):
    c = [cs(C[k]['n'])[0] for k in range(4)]
    s = [cs(C[k]['n'])[1] for k in range(4)]
    v = [C[i]['v'] for i in range(4)]; t0 = [C[i]['t0'] for i in range(4)]; t1 = [C[i]['t1'] for i in range(4)]
    e0 = [C[i]['e0'] for i in range(4)]; e1 = [C[i]['e1'] for i in range(4)]; f = [C[i]['f0'] for i in range(4)]
    gstar = sum(v[k] + 3 * e0[k] + 3 * e1[k] + 9 * f[k] for k in range(4)) / 64
    b211, b121 = [], []
    for i in range(4):
        ip = (i + 1) % 4
        kappa = 3 / (4 * (s[i] + s[ip]))
        b310 = (v[i] + 3 * t0[i]) / 4; b130 = (v[ip] + 3 * t1[ip]) / 4
        b211.append(b310 + (1 + c[i]) / 4 * (t1[ip] - t0[i]) + (1 - c[ip]) / 8 * (t0[i] - v[i]) + kappa * (f[i] - e0[i]))
        b121.append(b130 + (1 + c[ip]) / 4 * (t0[i] - t1[ip]) + (1 - c[i]) / 8 * (t1[ip] - v[ip]) + kappa * (f[ip] - e1[ip]))
    W = np.zeros((24, 3))
    for i in range(4):
        im, ip, i2 = (i - 1) % 4, (i + 1) % 4, (i + 2) % 4
        b112 = gstar + 3 / 16 * (b211[i] + b121[i] - b211[im] - b121[ip]) + 1 / 16 * (b211[ip] + b121[im] - b211[i2] - b121[i2])
        W[6 * i:6 * i + 6] = [v[i], t0[i], t1[i], b211[i], b121[i], b112]
    return W


def eval_face(scheme, C, ordinary):
    """positions (81, 3) and unnormalised normals (81, 3) of the face (acc: tangent-patch normal).
    A corner sample whose two derivatives are (near) collinear takes the normal 1e-6 inside the
    face, exactly as the ground truth does."""
    B = basis()
    if ordinary or scheme == 'regular':
        G = bicubic_ctrl(C); P = B['bicubic'][0] @ G
        Du, Dv = B['bicubic'][1] @ G, B['bicubic'][2] @ G
    elif scheme == 'acc':
        G = bicubic_ctrl(C); P = B['bicubic'][0] @ G
        T = acc_tangent_ctrl(C, G)
        Du, Dv = B['acc_tan'][0] @ T, B['acc_tan'][1] @ T
    elif scheme in ('gregory', 'gregory_osd'):
        G = gregory_ctrl(C)
        P, Du, Dv = (B['gregory'][k] @ G for k in range(3))
    elif scheme == 'pccm':
        G = cpatch_ctrl(C)
        P, Du, Dv = (B['cpatch'][k] @ G for k in range(3))
    else:
        raise ValueError(scheme)
    N = np.cross(Du[:81], Dv[:81])
    for c, (jj, ii) in enumerate(CORNER_SAMPLES):
        r = 9 * jj + ii
        if np.linalg.norm(N[r]) < 1e-6 * np.linalg.norm(Du[r]) * np.linalg.norm(Dv[r]):
            N[r] = np.cross(Du[81 + c], Dv[81 + c])
    return P[:81], N


# ---------------------------------------------------------------------------------------------
# accuracy against cc_limit
# ---------------------------------------------------------------------------------------------

ALL_SCHEMES = ['regular', 'acc', 'gregory', 'gregory_osd', 'pccm']


def measure(mesh, gt, scheme, variant='proposed', layout='sector', faces=None):
    """per-face arrays: pos error % (81,) and normal error deg (81,), ordinary flag."""
    vs = VertexStage(mesh, scheme, variant, layout)
    res = {}
    for f in (range(len(mesh.F)) if faces is None else faces):
        ordinary = all(mesh.corner_regular(x, f) for x in mesh.F[f])
        if scheme == 'regular' and not ordinary:
            continue
        C = [vs.corner(f, i) for i in range(4)]
        P, N = eval_face(scheme, C, ordinary)
        g = gt[f].reshape(81, 6)
        e = np.linalg.norm(P - g[:, :3], axis=1) / mesh.h[f] * 100
        a = angles_deg(N, g[:, 3:])
        res[f] = (e, a, ordinary)
    return res


def summarise(res, sel=None):
    E = [r[0] for f, r in res.items() if sel is None or sel(f, r)]
    A = [r[1] for f, r in res.items() if sel is None or sel(f, r)]
    if not E:
        return None
    E = np.concatenate(E); A = np.concatenate(A)
    return dict(n=len(E) // 81, rms=float(np.sqrt(np.mean(E ** 2))), max=float(E.max()),
                nrms=float(np.sqrt(np.mean(A ** 2))), nmax=float(A.max()))


OPEN = ['catmark_tent', 'catmark_single_crease', 'catmark_xord_boundary', 'catmark_xord_interior',
        'catmark_fvar_bound3', 'catmark_gregory_test1', 'catmark_pawn', 'catmark_car']
CLOSED = ['catmark_cube', 'catmark_righthanded']


def fmt(s):
    if s is None:
        return '%-38s' % '-'
    return '%6.3f / %7.3f  %6.3f / %7.3f' % (s['rms'], s['max'], s['nrms'], s['nmax'])


TABLE = []


def accuracy(names):
    print('\n== accuracy vs cc_limit: pos %% of local quad size (RMS / max), normal deg (RMS / max); '
          'semi-sharp creases as infinitely sharp (docs/boundaries.md) ==')
    print('%-22s %-11s %5s %-38s %-12s %-10s' % ('mesh', 'scheme', 'faces', 'pos rms/max %   normal rms/max deg',
                                               'reg.faces', 'reg max %'))
    regmax_all = 0.0
    for name in names:
        mesh = Mesh(name, 'sharp')
        gt = load_gt(name + '.bin')
        for scheme in ALL_SCHEMES:
            res = measure(mesh, gt, scheme)
            tot = summarise(res)
            if tot is None:
                continue
            # regular faces that the construction must reproduce exactly: ordinary and not
            # touching a semi-sharp edge (those are approximated by design)
            reg = summarise(res, lambda f, r: r[2] and mesh.face_touches_semi(f) == 0)
            regmax = reg['max'] if reg else float('nan')
            regn = reg['nmax'] if reg else float('nan')
            if reg:
                regmax_all = max(regmax_all, regmax)
            TABLE.append((name, scheme, tot, reg))
            print('%-22s %-11s %5d %s  %5d  %.1e %% / %.1e deg' % (name.replace('catmark_', ''), scheme, tot['n'], fmt(tot),
                                                                 reg['n'] if reg else 0, regmax, regn), flush=True)
            if reg:
                report('%s %s: regular faces reproduce the CC limit, max pos %%' % (name, scheme), regmax, 2e-3)
                report('%s %s: regular faces, max normal deg' % (name, scheme), reg['nmax'], 2e-3)
    return regmax_all


def layout_and_r(names):
    print('\n== gregory r at interior sharp positions: per-sector rows (ideal) vs the flat layout of '
          'docs/boundaries.md (position j0+m written by the next sector) vs sharp r[j] = 0 ==')
    for name in names:
        mesh = Mesh(name, 'sharp')
        if not any(c.get('sectors') and not c['boundary'] for c in mesh.info.values()):
            continue
        gt = load_gt(name + '.bin')
        for scheme in ('gregory', 'gregory_osd'):
            a = summarise(measure(mesh, gt, scheme, 'proposed', 'sector'), lambda f, r: not r[2])
            b = summarise(measure(mesh, gt, scheme, 'proposed', 'doc'), lambda f, r: not r[2])
            c = summarise(measure(mesh, gt, scheme, 'r0', 'sector'), lambda f, r: not r[2])
            print('  %-20s %-11s irregular faces: sector rows %s | doc layout %s | sharp r=0 %s'
                  % (name.replace('catmark_', ''), scheme, fmt(a), fmt(b), fmt(c)), flush=True)


EXACT = {}


def override_effect(names):
    print('\n== overrides, all faces: doc block (v + sharp e only) | virtual-ring tangents (+ acc/pccm sharp t) | '
          'adopted: + exact crease tangents for m >= 3 (boundary.md 3.3) ==')
    for name in names:
        mesh = Mesh(name, 'sharp')
        gt = load_gt(name + '.bin')
        for scheme in ('acc', 'gregory', 'gregory_osd', 'pccm'):
            a = summarise(measure(mesh, gt, scheme, 'doc'))
            b = summarise(measure(mesh, gt, scheme, 'virtual'))
            c = summarise(measure(mesh, gt, scheme, 'exact'))
            EXACT[(name, scheme)] = c
            print('  %-14s %-11s %s | %s | %s' % (name.replace('catmark_', ''), scheme, fmt(a), fmt(b), fmt(c)), flush=True)


def semi_sharp(names):
    print('\n== semi-sharp creases: faces with a corner on a semi-sharp edge, vs the tagged cc_limit; '
          'treatment "as infinitely sharp" (doc) vs "smooth" (tag ignored); grouped by sharpness ==')
    for name in names:
        mA, mB = Mesh(name, 'sharp'), Mesh(name, 'smooth')
        gt = load_gt(name + '.bin')
        for scheme in ('gregory', 'pccm', 'acc'):
            rA = measure(mA, gt, scheme); rB = measure(mB, gt, scheme)
            svals = sorted(set(mA.face_touches_semi(f) for f in range(len(mA.F))) - {0.0})
            for s in svals:
                sel = lambda f, r, s=s: mA.face_touches_semi(f) == s
                a, b = summarise(rA, sel), summarise(rB, sel)
                better = 'sharp' if a['rms'] < b['rms'] else 'smooth'
                print('  %-14s %-7s s=%-4g %3d faces  sharp: %s | smooth: %s  -> closer (pos rms): %s'
                      % (name.replace('catmark_', ''), scheme, s, a['n'], fmt(a), fmt(b), better), flush=True)
    # control: all tags ignored vs the .smooth ground truth
    for name in names:
        m = Mesh(name, 'none')
        gt = load_gt(name + '.smooth.bin')
        res = measure(m, gt, 'regular')
        reg = summarise(res)
        report('%s: tags ignored, regular faces vs .smooth.bin, max pos %%' % name, reg['max'], 2e-3)
        g = summarise(measure(m, gt, 'pccm'))
        print('         %s all tags ignored, pccm vs .smooth.bin: %s' % (name, fmt(g)))

# ---------------------------------------------------------------------------------------------
# stencil checks and golden values
# ---------------------------------------------------------------------------------------------

def pr(m):
    """partial-ring unit rows helper: returns (p, q(i), d(i)) as weight vectors of length 2m+2."""
    E = np.eye(2 * m + 2)
    return E[0], (lambda i: E[1 + 2 * i]), (lambda i: E[2 + 2 * i])


def check_stencils():
    print('\n== sector rows: affine sums, reductions to boundary.md section 4.3 ==')
    worst_p = worst_v = 0.0
    for scheme, (_, outs) in SCHEMES.items():
        for kind in ('crease', 'corner'):
            for m in range(1, 17):
                R = sector_rows(scheme, kind, m)
                for name, vec in outs:
                    rows = np.atleast_2d(R[name])
                    if vec:
                        worst_v = max(worst_v, np.abs(rows.sum(axis=1)).max())
                    else:
                        worst_p = max(worst_p, np.abs(rows.sum(axis=1) - 1).max())
    report('sector rows, every point row sums to 1 (5 schemes x crease/corner x m = 1..16)', worst_p, 1e-13)
    report('sector rows, every vector row sums to 0', worst_v, 1e-13)
    # regular at m = 2 (crease) and m = 1 (corner) = boundary.md section 4.3
    p, q, d = pr(2)
    L = (q(0) + 4 * p + q(2)) / 6
    want = {'v': L, 'e': [(2 * p + q(0)) / 3, (2 * (q(0) + 4 * p + q(2)) + d(0) + 4 * q(1) + d(1)) / 18, (2 * p + q(2)) / 3],
            'f': [(4 * p + 2 * q(0) + 2 * q(1) + d(0)) / 9, (4 * p + 2 * q(1) + 2 * q(2) + d(1)) / 9]}
    R = sector_rows('regular', 'crease', 2)
    err = max(np.abs(R['v'] - want['v']).max(), np.abs(R['e'] - np.array(want['e'])).max(),
              np.abs(R['f'][:2] - np.array(want['f'])).max())
    report('regular crease m=2 rows = boundary.md 4.3 Bezier points (L, (2p+q)/3, across edge point, face points)', err, 1e-15)
    p, q, d = pr(1)
    R = sector_rows('regular', 'corner', 1)
    err = max(np.abs(R['v'] - p).max(), np.abs(R['e'][0] - (2 * p + q(0)) / 3).max(),
              np.abs(R['e'][1] - (2 * p + q(1)) / 3).max(), np.abs(R['f'][0] - (4 * p + 2 * q(0) + 2 * q(1) + d(0)) / 9).max())
    report('regular corner m=1 rows = boundary.md 4.3 corner points (p, (2p+q0)/3, (2p+q1)/3, face point)', err, 1e-15)
    # the overrides are no-ops where the virtual ring is exact (m = 2 crease, m = 1 corner)
    worst = 0.0
    for scheme in SCHEMES:
        for kind, m in (('crease', 2), ('corner', 1)):
            Phi = virtual_ring(m)
            raw = run_block(scheme, Phi, 4)
            R = sector_rows(scheme, kind, m)
            for name, _ in SCHEMES[scheme][1]:
                a = np.array(raw[name][:m + 1]) if name in PER_POS else raw[name]
                worst = max(worst, np.abs(np.atleast_2d(a) - np.atleast_2d(R[name])).max())
    report('overrides are no-ops on the exact virtual rings (crease m=2, corner m=1), all schemes', worst, 1e-15)
    # at those m every scheme's corner points equal the regular scheme's (ordinary-patch sharing)
    worst = 0.0
    for scheme in ('acc', 'gregory', 'gregory_osd', 'pccm'):
        for kind, m in (('crease', 2), ('corner', 1)):
            A, B = sector_rows(scheme, kind, m), sector_rows('regular', kind, m)
            for name in ('v', 'e', 'f'):
                if name in A:
                    worst = max(worst, np.abs(np.atleast_2d(A[name]) - np.atleast_2d(B[name])).max())
            if scheme == 'pccm':
                worst = max(worst, np.abs(A['t'] - B['e']).max())
    report('acc/gregory/gregory_osd/pccm v, e, f (and pccm t) at crease m=2 / corner m=1 = regular rows', worst, 1e-15)
    # acc t scale: = 3(b10 - b00) of the regular patch; the across tangent at m=2 = boundary.md 3.3 (k=2)
    p, q, d = pr(2)
    A = sector_rows('acc', 'crease', 2); Rg = sector_rows('regular', 'crease', 2)
    err = max(np.abs(A['t'][0] - 3 * (Rg['e'][0] - Rg['v'])).max(), np.abs(A['t'][2] - 3 * (Rg['e'][2] - Rg['v'])).max(),
              np.abs(A['t'][1] - np.array([-4, -1, 1, 4, 1, -1]) / 6).max())
    report('acc t rows at crease m=2: sharp = 3(e - v), across = B-spline cross derivative (boundary.md 3.3)', err, 1e-15)
    # sharp-position values do not depend on the sector (both sides of an interior crease agree)
    worst = 0.0
    for scheme in SCHEMES:
        for kind in ('crease', 'corner'):
            for m1 in range(1, 6):
                for m2 in range(1, 6):
                    # shared edge: sector A's q_m = sector B's q_0; put both over [p, shared q, other q's]
                    A, B = sector_rows(scheme, kind, m1), sector_rows(scheme, kind, m2)
                    for name in ('e',) + (('t',) if scheme in ('acc', 'pccm') else ()):
                        a = A[name][m1]; b = B[name][0]
                        # weights on p and on the shared q must agree, all other weights must vanish
                        a_only = np.delete(a, [0, 2 * m1 + 1]); b_only = np.delete(b, [0, 1])
                        if name == 't' and scheme == 'acc' and kind == 'crease':
                            # (q_m - q_0)/2 of A = (q'_0 - q'_m')/2 of B for the *third* crease point
                            continue
                        worst = max(worst, abs(a[0] - b[0]), abs(a[2 * m1 + 1] - b[1]),
                                    np.abs(a_only).max(), np.abs(b_only).max())
    report('sharp-position rows (e; acc/pccm t) depend only on p and the sharp edge (sector-independent)', worst, 1e-15)
    # r at sharp positions IS sector-dependent (finding)
    A = sector_rows('gregory', 'crease', 2)
    report('INFO gregory r[m] of a crease sector uses the sector interior, weights of r[2] at m=2',
           ' '.join('%.4f' % x for x in A['r'][2]), kind='info')


def golden():
    fmt_s = ('sectors_reference.json, generated by docs/verify/sectors_verify.py --json (float64). '
             'schemes[scheme][kind][m] for kind in {crease, corner}, m = 1..4 sector faces: '
             '"virtual_valence" n\'(m); "outputs": list, in declaration order of the scheme\'s exported '
             'vertex definitions (not `let`), of {"name", "vector" (true: weights sum to 0, else 1), '
             '"per_position" (true: m + 1 rows for j = 0..m, else 1 row), "rows"}. Each row holds the '
             '2m + 2 weights over the partial ring [p, q_0, d_0, q_1, d_1, ..., d_{m-1}, q_m] '
             '(docs/boundaries.md section 2), i.e. table slots SECTOR_COLUMN + 0 .. 2m + 1. The rows are '
             'the scheme\'s vertex block evaluated on the virtual ring of docs/boundaries.md section 3 '
             'with the sector overrides of "overrides" (DSL lines) applied; rows in table order = '
             'outputs in order, each output\'s rows j = 0..m. "virtual_ring"[m]: the (2n\'+1) x (2m+2) '
             'matrix giving [p, p_0 .. p_{2n\'-1}] from the partial ring. "schemes_exact_crease_tangent"[scheme][m] '
             '(crease, m = 2..4; adopted in the .tess files for m >= 3, so m = 3, 4 equal "schemes" unless the file was '
             'written with --virtual-ring-tangents): as "schemes" without it, plus the crease tangents '
             't[j] = cos(pi j/m) (q_0 - q_m)/2 + sin(pi j/m) X, X = boundary.md 3.3 across mask, used for every '
             'position (acc t, gregory let t, pccm t = v + t/3, gregory_osd e = v + t/3) for m >= 3; m = 2 keeps '
             'the virtual ring (exact there) and equals "schemes".')
    out = {'format': fmt_s, 'virtual_ring': {}, 'schemes': {}}
    for m in range(1, 5):
        out['virtual_ring'][str(m)] = virtual_ring(m).tolist()
    out['schemes_exact_crease_tangent'] = {}
    for scheme, (_, outs) in SCHEMES.items():
        X = out['schemes_exact_crease_tangent'][scheme] = {}
        for m in range(2, 5):
            R = sector_rows(scheme, 'crease', m, 'exact')
            X[str(m)] = {'virtual_valence': virtual_valence(m), 'outputs': [
                {'name': name, 'vector': bool(vec), 'per_position': name in PER_POS,
                 'rows': np.atleast_2d(R[name]).tolist()} for name, vec in outs]}
    for scheme, (_, outs) in SCHEMES.items():
        S = out['schemes'][scheme] = {'overrides': {}}
        for kind in ('crease', 'corner'):
            S['overrides'][kind] = dsl_block(scheme, kind)
            S[kind] = {}
            for m in range(1, 5):
                R = sector_rows(scheme, kind, m)
                S[kind][str(m)] = {'virtual_valence': virtual_valence(m), 'outputs': [
                    {'name': name, 'vector': bool(vec), 'per_position': name in PER_POS,
                     'rows': np.atleast_2d(R[name]).tolist()} for name, vec in outs]}
    return out


# the adopted exact crease tangents (m >= 3) of the .tess crease blocks (ov_t_exact_*)
EXACT_DSL_COMMON = [
    'let th = pi / m;',
    'let lam = (cos(th) + 5 + sqrt((cos(th) + 9) * (cos(th) + 1))) / 16;',
    'let wf = 1 / (m * (3 + cos(th)));',
    'let we = 4 * (4 * lam - 1) * wf;',
    'let wc = ((3 * we / 8 + wf / 2) * cos(th / 2) / sin(th / 2) + (lam - 0.75) * (we / 2 + 2 * wf) * sin(th)) '
    '/ (8 * (lam - 0.75) * (lam - 0.5) - 1);',
    'let across = sum(k, (if k < m { 1 } else { 0 }) * (wf * (sin(k * th) + sin((k + 1) * th)) * (p[2 * k + 1] - p) '
    '+ we * sin(k * th) * (p[2 * k] - p))) + wc * (p[0] + p[2 * m] - 2 * p);',
]
_TJ = 'cos(j * th) * (p[0] - p[2 * m]) / 2 + sin(j * th) * across'
EXACT_DSL = {
    'acc': 't[j] = if m < 3 { t[j] } else { %s };' % _TJ,
    'gregory': 't[j] = if m < 3 { t[j] } else { %s };' % _TJ,
    'pccm': 't[j] = if m < 3 { t[j] } else { v + (%s) / 3 };' % _TJ,
    'gregory_osd': 'e[j] = if m < 3 { e[j] } else { v + (%s) / 3 };' % _TJ,
}


def dsl_block(scheme, kind):
    lines = []
    for name in overrides(scheme, kind):
        for key in ((scheme, kind, name), (scheme, '*', name), ('*', kind, name), ('*', '*', name)):
            if key in DSL_LINES:
                lines.append(DSL_LINES[key]); break
    if PROPOSED == 'exact' and kind == 'crease' and scheme in EXACT_DSL:
        lines += EXACT_DSL_COMMON + [EXACT_DSL[scheme]]
    return lines


def exact_across_mask(k):
    """boundary.md 3.3: exact across-crease limit tangent over the partial ring, k >= 2."""
    th = math.pi / k
    c = math.cos(2 * math.pi / (2 * k))
    lam = (c + 5 + math.sqrt((c + 9) * (c + 1))) / 16
    F = 1.0 / (k * (3.0 + math.cos(th))); E = 4.0 * (4.0 * lam - 1.0) * F
    sn = math.sin(th); C = 1.0 / math.tan(th / 2)
    w = np.zeros(2 * k + 2)
    for i in range(1, k):
        w[1 + 2 * i] = E * math.sin(i * th)
    for i in range(k):
        w[2 + 2 * i] = F * (math.sin(i * th) + math.sin((i + 1) * th))
    wc = ((3 * E / 8 + F / 2) * C + (lam - 0.75) * (E / 2 + 2 * F) * sn) / (8 * (lam - 0.75) * (lam - 0.5) - 1)
    w[0] = 8 * (wc * (lam - 0.5) - E * sn / 16 - F * sn / 4); w[1] = w[1 + 2 * k] = wc
    return w


def face_class(mesh, f):
    cls = set()
    for x in mesh.F[f]:
        c = mesh.info[x]
        if mesh.corner_regular(x, f):
            continue
        if c['rule'] == 'smooth':
            cls.add('EV n=%d' % c['n_layout'])
        elif c['rule'] == 'dart':
            cls.add('dart')
        else:
            k, _ = mesh.sector_of(x, f)
            cls.add('%s m=%d' % (c['rule'], c['sectors'][k]['m']))
    return ', '.join(sorted(cls)) or 'regular'


def diagnose(names):
    print('\n== diagnosis: irregular faces by corner class (pos rms/max %%, normal rms/max deg) ==')
    for name in names:
        mesh = Mesh(name, 'sharp'); gt = load_gt(name + '.bin')
        classes = {}
        for f in range(len(mesh.F)):
            if mesh.face_touches_semi(f) == 0:
                classes.setdefault(face_class(mesh, f), []).append(f)
        for scheme in ('gregory', 'pccm', 'acc'):
            res = measure(mesh, gt, scheme)
            for cl, fs in sorted(classes.items()):
                if cl == 'regular':
                    continue
                sm = summarise(res, lambda f, r, fs=set(fs): f in fs)
                print('  %-16s %-8s %-34s %3d faces %s' % (name.replace('catmark_', ''), scheme, cl[:34], sm['n'], fmt(sm)))
    print('\n== crease sectors m >= 3: normal at the vertex (corner sample) vs cc_limit [deg] ==')
    for name in names:
        mesh = Mesh(name, 'sharp'); gt = load_gt(name + '.bin')
        stats = {}
        vsg = {s: VertexStage(mesh, s) for s in ('gregory', 'pccm', 'acc')}
        for x, c in mesh.info.items():
            if c['rule'] != 'crease' or c['semi']:
                continue
            for sec in c['sectors']:
                m = sec['m']
                if m < 3:
                    continue
                R = mesh.V[sec['ring']]
                Ta = (R[1] - R[2 * m + 1]) / 2
                Tx = exact_across_mask(m) @ R
                for jl in range(m):
                    f = c['faces'][(sec['j0'] + jl) % len(c['faces'])]
                    i = mesh.F[f].index(x)
                    jj, ii = [(0, 0), (0, 8), (8, 8), (8, 0)][i]
                    g = gt[f, jj, ii, 3:]
                    st = stats.setdefault(m, {'exact': 0.0, 'gregory': 0.0, 'pccm': 0.0, 'acc': 0.0, 'n': 0})
                    st['exact'] = max(st['exact'], float(angles_deg(np.cross(Ta, Tx), g)))
                    st['n'] += 1
                    for s_, vs in vsg.items():
                        d = vs.corner(f, i)
                        if s_ == 'acc':
                            N = np.cross(d['t0'], d['t1'])
                        elif s_ == 'gregory':
                            N = np.cross(d['e0'] - d['v'], d['e1'] - d['v'])
                        else:
                            N = np.cross(d['t0'] - d['v'], d['t1'] - d['v'])
                        st[s_] = max(st[s_], float(angles_deg(N, g)))
        for m, st in sorted(stats.items()):
            print('  %-16s m=%d (%2d face corners): exact mask (boundary.md 3.3) %.2e | virtual ring: gregory %.3f  '
                  'pccm %.3f  acc %.3f' % (name.replace('catmark_', ''), m, st['n'], st['exact'], st['gregory'], st['pccm'], st['acc']))


def main():
    t0 = time.time()
    quick = '--quick' in sys.argv
    check_stencils()
    print('\n== proposed sector blocks ==')
    for scheme in SCHEMES:
        for kind in ('crease', 'corner'):
            print('  %-11s sector %s { %s }' % (scheme, kind, ' '.join(dsl_block(scheme, kind))))
    # topology sanity: sectors cover each ring position exactly once
    names = [n for n in OPEN if not (quick and n in ('catmark_pawn', 'catmark_car'))]
    bad = 0
    for name in names + CLOSED:
        mesh = Mesh(name)
        for x, c in mesh.info.items():
            if 'sectors' in c:
                cov = sorted((s['j0'] + k) % c['n_layout'] for s in c['sectors'] for k in range(s['count']))
                bad += int(cov != list(range(c['n_layout'])))
    report('sector counts write every ring position exactly once (all meshes)', float(bad), 0.0)
    regmax = accuracy(names + CLOSED)
    if '--diagnose' in sys.argv:
        diagnose([n for n in names if n not in ('catmark_car', 'catmark_pawn', 'catmark_single_crease')])
    override_effect(names)
    layout_and_r([n for n in names if n in ('catmark_single_crease', 'catmark_pawn', 'catmark_car')])
    semi_sharp([n for n in names if n in ('catmark_single_crease', 'catmark_pawn', 'catmark_car')])
    print('\n== targets: RMS distance <= 3 %, RMS normal <= 8 deg for pccm and gregory on every mesh ==')
    for name, scheme, tot, reg in TABLE:
        if scheme in ('pccm', 'gregory') and name in OPEN:
            ok = tot['rms'] <= 3 and tot['nrms'] <= 8
            x = EXACT.get((name, scheme))
            okx = x is not None and x['rms'] <= 3 and x['nrms'] <= 8
            print('  %-22s %-8s rms %.3f %% / %.3f deg  %-8s | with exact crease tangents: %.3f %% / %.3f deg  %s'
                  % (name, scheme, tot['rms'], tot['nrms'], 'met' if ok else 'NOT MET',
                     x['rms'], x['nrms'], 'met' if okx else 'NOT MET'))
    if '--json' in sys.argv:
        path = sys.argv[sys.argv.index('--json') + 1]
        with open(path, 'w') as fh:
            json.dump(golden(), fh, indent=1)
        print('\nwrote golden values to %s' % path)
    npf = sum(1 for r in ROWS if r.startswith('[PASS') or r.startswith('[FAIL'))
    print('\n%d checks, %d failed  (%.1f s)' % (npf, len(FAILS), time.time() - t0))
    if FAILS:
        print('FAILED: ' + '; '.join(FAILS))
        sys.exit(1)


if __name__ == '__main__':
    main()

#!/usr/bin/env python3
"""g1cc round 6: a G1 biquartic Gregory patch fitted to the Catmull-Clark limit (float64).

Self-contained but for its sibling g1cc_verify.py (mesh, ring and limit-mask helpers); numpy only.

The form (docs/g1cc.md, round 6): a 5x5 Bezier net b[a][b] (a along u) whose four twist points
b11, b31, b33, b13 are rationally blended pairs, as in the bicubic Gregory patch: 29 points.
Per vertex of valence n, ring p = [p, q0, d0, q1, d1, ...] (q_k = p[2k] edge neighbours, d_k
diagonals), constants theta_n (NAMES below):

  v      = CC limit point + PA (p - mean q) + PB (p - mean d)
  e[j]   = v + (A tq[j] + B td[j]) / 4          tq + td = exact CC limit tangent toward q_j
  h[j]   = v / 2 + sum_m al_m Cq_m[j] + be_m Cd_m[j]       cosine harmonics about edge j
  R_k[j] = sum_m Rkq_m Sq_m[j] + Rkd_m Sd_m[j]  (k = 1, 2, 3)  sine harmonics: antisymmetric
  g[j]   = sum_m gq_m Fq_m[j] + gd_m Fd_m[j]    cosine harmonics about the face diagonal d_j

Edge i of a face runs from corner a (ring slot j_a: the edge toward the next corner) to corner b
(slot j_b' = j_b + 1: b's edge toward a). Its quartic boundary is
  (v_a, e_a[j_a], h_a[j_a] + h_b[j_b'], e_b[j_b'], v_b):
every point is a vertex output or the sum of two, and fl(x + y) = fl(y + x), so both faces of
the edge get the same bits. The row next to it is b_k1 = P_k + rho_k / 2 + w_k (k = 1, 2, 3),
  rho_k = l0 (4 - k)/4 tau_k + l1 k/4 tau_{k-1},  tau_k = P_{k+1} - P_k,
  l0 = 2 cos(2 pi / n_a),  l1 = -2 cos(2 pi / n_b),  w_k = R_k^a[j_a] - R_{4-k}^b[j_b'],
so the two faces' cross-boundary derivatives add to lambda(t) T(t) with lambda linear: G1 for
every value of the constants (the face on the other side gets -w_k). Centre:
b22 = mean over the corners of v + g[slot of the face].

Every control point is affine in theta, so the fit is one linear least-squares solve: sum over
samples of |S - L|^2 / h^2 + wn ((N . S_u)^2 + (N . S_v)^2) / h^2 (N the exact limit normal;
N . S_u = 0 puts the patch's tangent in the limit tangent plane), on generic training polyhedra
(prisms, antiprisms, pyramids, bipyramids, trapezohedra, midpoint-refined, stretched, 10 % noise;
never the test meshes), against their exact Catmull-Clark limit (global subdivision to level 5,
then the regular bicubic B-spline of the level-5 face holding the sample).

Usage:
  python3 docs/verify/g1cc_quartic_verify.py                 # checks + the accuracy table (~1 min)
  python3 docs/verify/g1cc_quartic_verify.py --golden G.json # + golden control points / samples
  python3 docs/verify/g1cc_quartic_verify.py --fit           # re-derive the table (~15 min)
  python3 docs/verify/g1cc_quartic_verify.py --bound         # best unconstrained polynomials (~3 min)
  python3 docs/verify/g1cc_quartic_verify.py --sectors       # + meshes with boundaries and creases (~1 min)
  python3 docs/verify/g1cc_quartic_verify.py --holdout       # + valences 17..32 on held-out meshes (~1 min)
  python3 docs/verify/g1cc_quartic_verify.py --tess PATH     # write the scheme file g1cc.tess + its checks (~10 s)
"""
import functools
import json
import math
import os
import re
import sys
import time
from math import comb
from types import SimpleNamespace

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import g1cc_verify as G  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
TABLE_PATH = os.path.join(HERE, 'g1cc_quartic_table.json')
NH = 3  # harmonics m = 1..NH (m = 0 too for the symmetric ones)
NAMES = ['PA', 'PB', 'A', 'B'] + [f'al{m}' for m in range(NH + 1)] + [f'be{m}' for m in range(NH + 1)] \
    + [f'R{k}{s}{m}' for k in (1, 2, 3) for s in 'qd' for m in range(1, NH + 1)] \
    + [f'gq{m}' for m in range(NH + 1)] + [f'gd{m}' for m in range(NH + 1)]
NP = len(NAMES)
IDX = {nm: i for i, nm in enumerate(NAMES)}
FIT_WN = 100.0
MAX_N = 32  # codegen's DEFAULT_MAX_VALENCE
CLOSED = ['catmark_cube', 'catmark_toroidal_tet', 'catmark_righthanded', 'catmark_torus']


# ==================================================================== exact Catmull-Clark limit
C4 = np.array([(0., 0.), (1., 0.), (1., 1.), (0., 1.)])


def cc_step(V, F):
    """One Catmull-Clark step of a closed quad mesh; child 4f + i sits at corner i of face f,
    (corner, edge point of edge i, face point, edge point of edge i - 1)."""
    nv, m = len(V), len(F)
    fp = V[F].mean(1)
    e = np.sort(np.stack([F, np.roll(F, -1, 1)], 2).reshape(-1, 2), 1)
    uk, inv = np.unique(e[:, 0] * nv + e[:, 1], return_inverse=True)
    inv = inv.reshape(-1)
    ea, eb = uk // nv, uk % nv
    s = np.zeros((len(uk), 3))
    np.add.at(s, inv, fp[np.repeat(np.arange(m), 4)])
    ep = (V[ea] + V[eb] + s) / 4
    val = np.zeros(nv); Q = np.zeros((nv, 3)); R = np.zeros((nv, 3))
    np.add.at(val, F.reshape(-1), 1); np.add.at(Q, F.reshape(-1), np.repeat(fp, 4, 0))
    mid = (V[ea] + V[eb]) / 2
    np.add.at(R, ea, mid); np.add.at(R, eb, mid)
    n = val[:, None]
    Vn = np.vstack([(Q / n + 2 * R / n + (n - 3) * V) / n, ep, fp])
    EI = inv.reshape(m, 4)
    Fn = np.zeros((m, 4, 4), int)
    for i in range(4):
        Fn[:, i] = np.c_[F[:, i], nv + EI[:, i], nv + len(uk) + np.arange(m), nv + EI[:, (i - 1) % 4]]
    return Vn, Fn.reshape(-1, 4)


class Limit:
    """Exact limit position and (u, v)-derivatives: subdivide K times, then evaluate the regular
    bicubic B-spline of the level-K face that holds the sample (None inside an irregular one)."""

    def __init__(self, V, F, K):
        self.K = K
        V, F = np.asarray(V, float), np.array(F, int)
        for _ in range(K):
            V, F = cc_step(V, F)
        self.V, self.F = V, F
        self.reg = (np.bincount(F.reshape(-1), minlength=len(V))[F] == 4).all(1)
        self.he = {(f[k], f[(k + 1) % 4]): (fi, k) for fi, f in enumerate(F) for k in range(4)}

    def _ring(self, fi, k):
        f = self.F[fi]; x = f[k]; a = f[(k + 1) % 4]; out = []
        for _ in range(4):
            g, kk = self.he[(x, a)]
            out += [self.F[g][(kk + 1) % 4], self.F[g][(kk + 2) % 4]]
            a = self.F[g][(kk + 3) % 4]
        return out

    def _grid(self, fi):
        ra, rb, rc, rd = (self._ring(fi, k) for k in range(4))
        g = np.zeros((4, 4), int)
        g[1, 1], g[2, 1], g[2, 2], g[1, 2] = self.F[fi]
        g[0, 2], g[0, 1], g[0, 0], g[1, 0], g[2, 0] = ra[3:8]
        g[3, 1], g[3, 2], g[3, 3], g[2, 3], g[1, 3] = rc[3:8]
        g[3, 0], g[0, 3] = rb[5], rd[5]
        return self.V[g]

    def eval(self, face, u, v):
        fi, o, A, x = face, np.zeros(2), np.eye(2), np.array([u, v])
        for _ in range(self.K):
            st = np.linalg.solve(A, x - o)
            for i in range(4):
                Ac = np.c_[(C4[(i + 1) % 4] - C4[i]) / 2, (C4[(i - 1) % 4] - C4[i]) / 2]
                sc = np.linalg.solve(Ac, st - C4[i])
                if (sc >= -1e-12).all() and (sc <= 1 + 1e-12).all():
                    break
            o, A, fi = o + A @ C4[i], A @ Ac, 4 * fi + i
        if not self.reg[fi]:
            return None
        s, t = np.linalg.solve(A, x - o)
        J = np.linalg.inv(A)
        g = self._grid(fi)
        b = lambda t: np.array([(1 - t) ** 3, 3 * t ** 3 - 6 * t * t + 4, -3 * t ** 3 + 3 * t * t + 3 * t + 1, t ** 3]) / 6
        db = lambda t: np.array([-3 * (1 - t) ** 2, 9 * t * t - 12 * t, -9 * t * t + 6 * t + 3, 3 * t * t]) / 6
        P = np.einsum('i,j,ijc->c', b(s), b(t), g)
        Ps = np.einsum('i,j,ijc->c', db(s), b(t), g)
        Pt = np.einsum('i,j,ijc->c', b(s), db(t), g)
        return P, Ps * J[0, 0] + Pt * J[1, 0], Ps * J[0, 1] + Pt * J[1, 1]


def limit_samples(V, F, faces, M, K):
    """(len(faces), M, M, 9): P, P_u, P_v on an M x M grid ([j, i]: u = i/(M-1), v = j/(M-1));
    NaN where the sample lies in an irregular level-K face (extraordinary corners)."""
    L = Limit(V, F, K)
    S = np.full((len(faces), M, M, 9), np.nan)
    for a, fi in enumerate(faces):
        for j in range(M):
            for i in range(M):
                r = L.eval(fi, i / (M - 1), j / (M - 1))
                if r is not None:
                    S[a, j, i] = np.concatenate(r)
    return S


# ==================================================================== generic training polyhedra
def refine(V, F):
    """Topological split with centroids and midpoints: any polygon mesh -> quads."""
    V = [np.array(p, float) for p in V]; eid = {}; Q = []; fpts = []
    for f in F:
        fpts.append(len(V)); V.append(np.mean([V[x] for x in f], axis=0))
    key = lambda a, b: (min(a, b), max(a, b))
    for f in F:
        for k in range(len(f)):
            kk = key(f[k], f[(k + 1) % len(f)])
            if kk not in eid:
                eid[kk] = len(V); V.append((V[kk[0]] + V[kk[1]]) / 2)
    for fi, f in enumerate(F):
        for k in range(len(f)):
            Q.append([f[k], eid[key(f[k], f[(k + 1) % len(f)])], fpts[fi], eid[key(f[k], f[k - 1])]])
    return np.array(V), Q


def _ring_pts(n, z, phase=0.0):
    a = 2 * np.pi * np.arange(n) / n + phase
    return np.c_[np.cos(a), np.sin(a), np.full(n, z)]


def polyhedra(n):
    r = list(range(n))
    yield 'prism', np.vstack([_ring_pts(n, -0.6), _ring_pts(n, 0.6)]), \
        [r[::-1], [n + i for i in r]] + [[i, (i + 1) % n, n + (i + 1) % n, n + i] for i in r]
    yield 'antiprism', np.vstack([_ring_pts(n, -0.5), _ring_pts(n, 0.5, np.pi / n)]), \
        [r[::-1], [n + i for i in r]] + sum([[[i, (i + 1) % n, n + i], [(i + 1) % n, n + (i + 1) % n, n + i]] for i in r], [])
    yield 'pyramid', np.vstack([_ring_pts(n, -0.5), [[0, 0, 0.9]]]), [r[::-1]] + [[i, (i + 1) % n, n] for i in r]
    yield 'bipyramid', np.vstack([_ring_pts(n, 0.0), [[0, 0, 1.0]], [[0, 0, -1.0]]]), \
        [[i, (i + 1) % n, n] for i in r] + [[(i + 1) % n, i, n + 1] for i in r]
    yield 'trapezohedron', np.vstack([0.25 * _ring_pts(n, 1.0) * [4, 4, 1], _ring_pts(n, -0.25, np.pi / n),
                                      [[0, 0, 1.1]], [[0, 0, -1.1]]]), \
        sum([[[2 * n, i, n + i, (i + 1) % n], [2 * n + 1, n + (i + 1) % n, (i + 1) % n, n + i]] for i in r], [])


def outward(V, F):
    vol = sum(np.dot(V[f[0]], np.cross(V[f[k]], V[f[k + 1]])) for f in F for k in range(1, len(f) - 1))
    return F if vol > 0 else [f[::-1] for f in F]


def training_set(seed, copies, noise, valences):
    rng = np.random.default_rng(seed)
    for n in valences:
        for name, V0, F0 in polyhedra(n):
            V, F = refine(V0, outward(V0, F0))
            h = np.median([np.linalg.norm(V[f[0]] - V[f[1]]) for f in F])
            for c in range(copies):
                yield f'{name}{n}_{c}', V @ np.diag(rng.uniform(0.6, 1.6, 3)) + rng.normal(0, noise * h, V.shape), F


# ==================================================================== the form, affine in theta
class Ex:
    """c + theta @ a: c (3,), a (P, 3)."""
    __slots__ = ('c', 'a')

    def __init__(self, c, a):
        self.c, self.a = c, a

    def __add__(s, o): return Ex(s.c + o.c, s.a + o.a)
    def __sub__(s, o): return Ex(s.c - o.c, s.a - o.a)
    def __mul__(s, k): return Ex(s.c * k, s.a * k)
    __rmul__ = __mul__
    def __truediv__(s, k): return Ex(s.c / k, s.a / k)


class Layout:
    """Which valences' constants are unknowns (columns of theta); the rest come from `fixed`."""

    def __init__(self, free, fixed):
        self.free, self.fixed, self.P = list(free), fixed, NP * len(free)

    def term(self, n, name, vec):
        if n in self.free:
            a = np.zeros((self.P, 3)); a[NP * self.free.index(n) + IDX[name]] = vec
            return Ex(np.zeros(3), a)
        return Ex(self.fixed[n][IDX[name]] * vec, np.zeros((self.P, 3)))

    def const(self, x):
        return Ex(np.asarray(x, float), np.zeros((self.P, 3)))


def _iq(n, k): return 1 + 2 * (k % n)
def _id(n, k): return 2 + 2 * (k % n)


def _cos_h(n, j, m, off_q, off_d):
    """(1/n) sum_k cos(2 pi m (k - j + off) / n) (x_k - p) for x = q and x = d."""
    q = np.zeros(2 * n + 1); d = np.zeros(2 * n + 1)
    for k in range(n):
        cq = math.cos(2 * math.pi * m * (k - j + off_q) / n) / n
        cd = math.cos(2 * math.pi * m * (k - j + off_d) / n) / n
        q[_iq(n, k)] += cq; q[0] -= cq; d[_id(n, k)] += cd; d[0] -= cd
    return q, d


def _sin_h(n, j, m):
    q = np.zeros(2 * n + 1); d = np.zeros(2 * n + 1)
    for k in range(n):
        q[_iq(n, k)] += math.sin(2 * math.pi * m * (k - j) / n) / n
        d[_id(n, k)] += math.sin(2 * math.pi * m * (k - j + 0.5) / n) / n
    return q, d


_MASKS = {}


def masks(n):
    if n not in _MASKS:
        wa = np.zeros(2 * n + 1); wa[0] = 1; wa[1::2] -= 1 / n
        wb = np.zeros(2 * n + 1); wb[0] = 1; wb[2::2] -= 1 / n
        _MASKS[n] = dict(
            L=G.limit_mask(n), wa=wa, wb=wb, T=[G.tangent_parts(n, j) for j in range(n)],
            CH=[[_cos_h(n, j, m, 0.0, 0.5) for m in range(NH + 1)] for j in range(n)],
            SH=[[_sin_h(n, j, m) for m in range(1, NH + 1)] for j in range(n)],
            FH=[[_cos_h(n, j, m, -0.5, 0.0) for m in range(NH + 1)] for j in range(n)])
    return _MASKS[n]


class Vertex:
    """The vertex outputs v, e[j], h[j], R_k[j], g[j] of one vertex."""

    def __init__(self, lay, pts, n):
        M = masks(n); self.n = n
        t = lambda name, mask: lay.term(n, name, mask @ pts)
        self.v = lay.const(M['L'] @ pts) + t('PA', M['wa']) + t('PB', M['wb'])
        self.e, self.h, self.R, self.g = [], [], [], []
        for j in range(n):
            tq, td = M['T'][j]
            self.e.append(self.v + (t('A', tq) + t('B', td)) / 4)
            h = self.v / 2
            for m in range(NH + 1):
                h = h + t(f'al{m}', M['CH'][j][m][0]) + t(f'be{m}', M['CH'][j][m][1])
            self.h.append(h)
            R = {}
            for k in (1, 2, 3):
                r = lay.const(np.zeros(3))
                for m in range(1, NH + 1):
                    r = r + t(f'R{k}q{m}', M['SH'][j][m - 1][0]) + t(f'R{k}d{m}', M['SH'][j][m - 1][1])
                R[k] = r
            self.R.append(R)
            g = lay.const(np.zeros(3))
            for m in range(NH + 1):
                g = g + t(f'gq{m}', M['FH'][j][m][0]) + t(f'gd{m}', M['FH'][j][m][1])
            self.g.append(g)


def _slot(i, k, depth):
    """Grid index of point k (0..4) of edge i at `depth` rows inside."""
    return [(k, depth), (4 - depth, k), (4 - k, 4 - depth), (depth, 4 - k)][i]


TWIST = {(1, 1): (0, 0), (3, 1): (1, 0), (3, 3): (1, 1), (1, 3): (0, 1)}  # (u far?, v far?)


def patch(corners):
    """corners: [(Vertex, j)] CCW, j = ring slot of the edge toward the next corner.
    Keys: (a, b) grid points; ('h', (a, b)) / ('v', (a, b)) the twist pair, defined by the
    horizontal (v = 0, 1) and the vertical (u = 0, 1) edge."""
    cp = {}
    for i in range(4):
        A, ja = corners[i]; B, jb = corners[(i + 1) % 4]
        jb1 = (jb + 1) % B.n
        P = [A.v, A.e[ja], A.h[ja] + B.h[jb1], B.e[jb1], B.v]
        for k in range(5):
            cp[_slot(i, k, 0)] = P[k]
        tau = [P[k + 1] - P[k] for k in range(4)]
        l0, l1 = 2 * math.cos(2 * math.pi / A.n), -2 * math.cos(2 * math.pi / B.n)
        for k in (1, 2, 3):
            X = P[k] + (tau[k] * (l0 * (4 - k) / 4) + tau[k - 1] * (l1 * k / 4)) / 2 + A.R[ja][k] - B.R[jb1][4 - k]
            s = _slot(i, k, 1)
            cp[s if k == 2 else ('h' if i % 2 == 0 else 'v', s)] = X
    c = None
    for A, ja in corners:
        x = (A.v + A.g[ja]) / 4
        c = x if c is None else c + x
    cp[(2, 2)] = c
    return cp


KEYS = [(a, b) for a in range(5) for b in range(5) if (a, b) not in TWIST] + [(s, t) for t in TWIST for s in 'hv']


def _bern(d, t): return np.array([comb(d, i) * t ** i * (1 - t) ** (d - i) for i in range(d + 1)])
def _dbern(d, t): b = _bern(d - 1, t); return d * (np.r_[0, b] - np.r_[b, 0])


_BASIS = {}


def basis(us, vs):
    """(3, S, 29): weights of position, d/du, d/dv (exact, blend derivatives included)."""
    key = (tuple(np.round(us, 12)), tuple(np.round(vs, 12)))
    if key in _BASIS:
        return _BASIS[key]
    col = {k: i for i, k in enumerate(KEYS)}
    W = np.zeros((3, len(us), len(KEYS)))
    for s, (u, v) in enumerate(zip(us, vs)):
        Bu, Bv, dBu, dBv = _bern(4, u), _bern(4, v), _dbern(4, u), _dbern(4, v)
        for a in range(5):
            for b in range(5):
                w, wu, wv = Bu[a] * Bv[b], dBu[a] * Bv[b], Bu[a] * dBv[b]
                if (a, b) not in TWIST:
                    W[:, s, col[(a, b)]] += (w, wu, wv)
                    continue
                fu, fv = TWIST[(a, b)]
                du, ddu = (1 - u, -1.0) if fu else (u, 1.0)
                dv, ddv = (1 - v, -1.0) if fv else (v, 1.0)
                sm = du + dv
                if sm < 1e-300:
                    wh, whu, whv = 0.5, 0.0, 0.0  # the corner: its Bernstein weight is 0 there
                else:  # the horizontal-edge point dominates as dv -> 0
                    wh, whu, whv = du / sm, ddu * dv / sm ** 2, -du * ddv / sm ** 2
                W[:, s, col[('h', (a, b))]] += (w * wh, wu * wh + w * whu, wv * wh + w * whv)
                W[:, s, col[('v', (a, b))]] += (w * (1 - wh), wu * (1 - wh) - w * whu, wv * (1 - wh) - w * whv)
    _BASIS[key] = W
    return W


def face_cp(lay, mesh, fi, cache):
    """(C, A): the face's 29 control points are C + theta @ A."""
    cs = []
    for i in range(4):
        x, n, j = mesh.slot(fi, i)
        if x not in cache:
            cache[x] = Vertex(lay, mesh.V[[x] + mesh.rings[x]], n)
        cs.append((cache[x], j))
    cp = patch(cs)
    return np.array([cp[k].c for k in KEYS]), np.array([cp[k].a for k in KEYS])


def table_layout(table):
    """A layout with no unknowns: every valence's constants from the table."""
    return Layout([], {int(n): np.array([c[nm] for nm in NAMES]) for n, c in table.items()})


def mesh_cps(table, mesh):
    lay = table_layout(table); cache = {}
    return [face_cp(lay, mesh, fi, cache)[0] for fi in range(len(mesh.F))]


# ==================================================================== fit
def accumulate(lay, mesh, faces, S, wn, AtA, Atb):
    cache = {}
    M = S.shape[1]; g = np.linspace(0, 1, M); UU, VV = np.meshgrid(g, g)
    for a, fi in enumerate(faces):
        f = mesh.F[fi]; h = np.mean([np.linalg.norm(mesh.V[f[k]] - mesh.V[f[(k + 1) % 4]]) for k in range(4)])
        P = S[a][..., :3].copy(); N = np.cross(S[a][..., 3:6], S[a][..., 6:9])
        ok = ~np.isnan(P[..., 0])
        for i, (jj, ii) in enumerate([(0, 0), (0, M - 1), (M - 1, M - 1), (M - 1, 0)]):
            if not ok[jj, ii]:  # an extraordinary corner: limit point and tangent plane from masks
                x, n, j = mesh.slot(fi, i); pts = mesh.V[[x] + mesh.rings[x]]
                P[jj, ii] = G.limit_mask(n) @ pts
                N[jj, ii] = np.cross(sum(G.tangent_parts(n, j)) @ pts, sum(G.tangent_parts(n, (j + 1) % n)) @ pts)
                ok[jj, ii] = True
        N = N / np.linalg.norm(N, axis=-1, keepdims=True)
        P, N = P[ok], N[ok]
        W = basis(UU[ok], VV[ok])
        C, A = face_cp(lay, mesh, fi, cache)
        rows = [W[0] @ A[:, :, x] / h for x in range(3)]
        rhs = [(P[:, x] - W[0] @ C[:, x]) / h for x in range(3)]
        for d in (1, 2):
            rows.append(math.sqrt(wn) * sum(N[:, x:x + 1] * (W[d] @ A[:, :, x]) for x in range(3)) / h)
            rhs.append(-math.sqrt(wn) * sum(N[:, x] * (W[d] @ C[:, x]) for x in range(3)) / h)
        R = np.vstack(rows); b = np.concatenate(rhs)
        AtA += R.T @ R; Atb += R.T @ b


def solve(lay, sets, wn, ridge=1e-6, prior=None):
    """Normal equations; ridge (relative to the mean diagonal) > 0 for the fit, 0 for the exact
    n = 4 solve, whose aliased harmonics make it rank-deficient (minimum-norm solution). With a
    prior the ridge pulls towards it instead of towards 0."""
    AtA = np.zeros((lay.P, lay.P)); Atb = np.zeros(lay.P)
    for mesh, faces, S in sets:
        accumulate(lay, mesh, faces, S, wn, AtA, Atb)
    if ridge == 0:
        return np.linalg.lstsq(AtA, Atb, rcond=None)[0]
    r = ridge * np.trace(AtA) / lay.P
    return np.linalg.solve(AtA + r * np.eye(lay.P), Atb + (0 if prior is None else r * prior))


def torus_grid(m=6, seed=1):
    rng = np.random.default_rng(seed); V = []; F = []
    for j in range(m):
        for i in range(m):
            a, b = 2 * np.pi * i / m, 2 * np.pi * j / m
            V.append([(2 + np.cos(b)) * np.cos(a), (2 + np.cos(b)) * np.sin(a), np.sin(b)])
            F.append([j * m + i, j * m + (i + 1) % m, ((j + 1) % m) * m + (i + 1) % m, ((j + 1) % m) * m + i])
    return np.array(V) + rng.normal(0, 0.2, (m * m, 3)), F


def fit(wn=FIT_WN):
    """n = 4 first, on a noisy regular torus (its limit is the bicubic B-spline: the fit must be
    exact); then n = 3, 5..16 together on the training polyhedra."""
    t0 = time.time()
    V, F = torus_grid(); mesh = G.Mesh(V, F)
    lay4 = Layout([4], {})
    th4 = solve(lay4, [(mesh, list(range(len(F))), limit_samples(V, F, range(len(F)), 9, 0))], 0.0, ridge=0)
    table = {4: th4}
    sets = []
    for seed, copies, vals in [(7, 2, range(3, 9)), (11, 1, range(9, 17))]:
        for name, V, F in training_set(seed, copies, 0.10, vals):
            mesh = G.Mesh(V, F)
            faces = [fi for fi in range(len(F)) if any(mesh.slot(fi, i)[1] != 4 for i in range(4))]
            sets.append((mesh, faces, limit_samples(V, F, faces, 13, 5)))
            print(f'  {name}: {len(faces)} faces ({time.time() - t0:.0f} s)', flush=True)
    free = [3] + list(range(5, 17))
    th = solve(Layout(free, table), sets, wn)
    for k, n in enumerate(free):
        table[n] = th[NP * k:NP * (k + 1)]
    # n = 17..32 (the default stencil table's range) on their own, n <= 16 held: prisms,
    # pyramids and bipyramids, one copy each -- three meshes per valence, so the ridge is 0.1 and
    # pulls towards the n = 16 row (on held-out antiprisms and trapezohedra of n = 18, 24, 30 this
    # beats both the plain fit and the n = 16 row itself, docs/g1cc.md).
    sets = []
    for name, V, F in high_valence_set():
        mesh = G.Mesh(V, F)
        faces = [fi for fi in range(len(F)) if any(mesh.slot(fi, i)[1] > 16 for i in range(4))]
        sets.append((mesh, faces, limit_samples(V, F, faces, 13, 5)))
        print(f'  {name}: {len(faces)} faces ({time.time() - t0:.0f} s)', flush=True)
    free = list(range(17, MAX_N + 1))
    th = solve(Layout(free, table), sets, wn, ridge=0.1, prior=np.concatenate([table[16]] * len(free)))
    for k, n in enumerate(free):
        table[n] = th[NP * k:NP * (k + 1)]
    return {str(n): {nm: float(x) for nm, x in zip(NAMES, table[n])} for n in sorted(table)}


def high_valence_set(seed=13):
    rng = np.random.default_rng(seed)
    for n in range(17, MAX_N + 1):
        for name, V0, F0 in polyhedra(n):
            if name not in ('prism', 'pyramid', 'bipyramid'):
                continue
            V, F = refine(V0, outward(V0, F0))
            h = np.median([np.linalg.norm(V[f[0]] - V[f[1]]) for f in F])
            yield f'{name}{n}', V @ np.diag(rng.uniform(0.6, 1.6, 3)) + rng.normal(0, 0.10 * h, V.shape), F


# ==================================================================== checks and measures
def measure(table, name):
    V, F = G.load_obj(G._data(f'meshes/{name}.obj')); lim = G.load_limit(name); mesh = G.Mesh(V, F)
    t8 = np.arange(9) / 8; U8, V8 = np.meshgrid(t8, t8)
    W = basis(U8.ravel(), V8.ravel())
    D, An = [], []
    for fi, cp in enumerate(mesh_cps(table, mesh)):
        f = F[fi]; L = lim[fi].reshape(-1, 6)
        h = np.mean([np.linalg.norm(V[f[k]] - V[f[(k + 1) % 4]]) for k in range(4)])
        D.append(np.linalg.norm(W[0] @ cp - L[:, :3], axis=1) / h * 100)
        An.append(G.angle_deg(np.cross(W[1] @ cp, W[2] @ cp), L[:, 3:]))
    D, An = np.concatenate(D), np.concatenate(An)
    return mesh, dict(rms_d=math.sqrt((D ** 2).mean()), max_d=D.max(), rms_n=math.sqrt((An ** 2).mean()), max_n=An.max())


def edge_check(cps, mesh, ts=np.linspace(0, 1, 17)):
    """Max true-normal angle and max position gap between the two patches of every edge."""
    uv = lambda k, t: [(t, 0.0), (1.0, t), (1 - t, 1.0), (0.0, 1 - t)][k]
    wa = wp = 0.0
    for (a, b), (fa, ka) in mesh.he.items():
        if a > b or (b, a) not in mesh.he:
            continue
        fb, kb = mesh.he[(b, a)]
        for t in ts:
            Wa = basis(*([x] for x in uv(ka, t))); Wb = basis(*([x] for x in uv(kb, 1 - t)))
            A, B = cps[fa], cps[fb]
            wp = max(wp, float(np.abs(Wa[0] @ A - Wb[0] @ B).max()))
            wa = max(wa, float(G.angle_deg(np.cross(Wa[1] @ A, Wa[2] @ A), np.cross(Wb[1] @ B, Wb[2] @ B)).max()))
    return wa, wp


def random_table(rng):
    return {str(n): {nm: float(rng.normal(0, 0.3)) for nm in NAMES} for n in range(3, MAX_N + 1)}


def check_g1_random(rng, trials=1):
    """Two faces A = (v0, v1, d0, q1), B = (v1, v0, q_{n0-1}, d_{n0-1}) sharing the edge v0 v1,
    random rings of valences n0, n1 = 3..MAX_N, random far corners, random tables: max angle
    between the true normals along the shared edge, and max position gap."""
    lay = table_layout(random_table(rng)); worst_a = worst_p = 0.0
    ts = np.linspace(0, 1, 9)
    for n0 in range(3, MAX_N + 1):
        for n1 in range(3, MAX_N + 1):
            for _ in range(trials):
                p0 = rng.normal(0, 0.2, 3)
                ring0 = [np.array([math.cos(2 * math.pi * k / n0), math.sin(2 * math.pi * k / n0), 0.0])
                         * (1 + 0.3 * rng.uniform(-1, 1)) + rng.normal(0, 0.25, 3) for k in range(2 * n0)]
                q = lambda k: ring0[2 * (k % n0)]; d = lambda k: ring0[2 * (k % n0) + 1]
                v1 = q(0); s = int(rng.integers(n1)); ring1 = [None] * (2 * n1)
                for off, x in enumerate([d(0), q(1), p0, q(n0 - 1), d(n0 - 1)]):
                    ring1[(2 * s + off) % (2 * n1)] = x
                for k in range(2 * n1):
                    if ring1[k] is None:
                        ang = math.pi + 2 * math.pi * (k - 2 * s - 2) / (2 * n1)
                        ring1[k] = v1 + 1.2 * np.array([math.cos(ang), math.sin(ang), 0]) + rng.normal(0, 0.3, 3)
                A0 = Vertex(lay, np.array([p0] + ring0), n0); A1 = Vertex(lay, np.array([v1] + ring1), n1)
                far = lambda: (lambda nn: (Vertex(lay, rng.normal(0, 1, (2 * nn + 1, 3)), nn), int(rng.integers(nn))))(int(rng.integers(3, 9)))
                cA, cB = patch([(A0, 0), (A1, s), far(), far()]), patch([(A1, (s + 1) % n1), (A0, n0 - 1), far(), far()])
                CA = np.array([cA[k].c for k in KEYS]); CB = np.array([cB[k].c for k in KEYS])
                for t in ts:
                    Wa, Wb = basis([t], [0.0]), basis([1 - t], [0.0])
                    worst_p = max(worst_p, float(np.abs(Wa[0] @ CA - Wb[0] @ CB).max()))
                    worst_a = max(worst_a, float(G.angle_deg(np.cross(Wa[1] @ CA, Wa[2] @ CA),
                                                             np.cross(Wb[1] @ CB, Wb[2] @ CB)).max()))
    return worst_a, worst_p


def check_affine(rng, table):
    """Every control point moves with a translation of the ring (stencils sum to 1)."""
    worst = 0.0
    for n in range(3, MAX_N + 1):
        V0, F0 = next(polyhedra(n))[1:]
        V, F = refine(V0, outward(V0, F0)); mesh = G.Mesh(V + rng.normal(0, 0.2, V.shape), F)
        a = mesh_cps(table, mesh)
        mesh.V = mesh.V + np.array([3.0, -7.0, 11.0])
        b = mesh_cps(table, mesh)
        worst = max(worst, max(float(np.abs(y - x - [3.0, -7.0, 11.0]).max()) for x, y in zip(a, b)))
    return worst


def check_limit():
    """The exact-limit evaluator against cc_limit (f32 storage): every level-8 sample but the
    extraordinary corners (level 4 is enough: the nearest sample is 1/8 from the corner)."""
    worst_p = worst_n = 0.0; count = 0
    for name in ('catmark_cube', 'catmark_toroidal_tet'):
        V, F = G.load_obj(G._data(f'meshes/{name}.obj')); lim = G.load_limit(name)
        S = limit_samples(V, F, range(len(F)), 9, 4)
        ok = ~np.isnan(S[..., 0])
        scale = np.abs(V).max()
        worst_p = max(worst_p, float(np.abs(S[..., :3][ok] - lim[..., :3][ok]).max() / scale))
        worst_n = max(worst_n, float(G.angle_deg(np.cross(S[..., 3:6], S[..., 6:9])[ok], lim[..., 3:][ok]).max()))
        count += int(ok.sum())
    return worst_p, worst_n, count


def check_regular(table):
    V, F = torus_grid(seed=5); mesh = G.Mesh(V, F)
    S = limit_samples(V, F, range(len(F)), 5, 0)
    W = basis(*(np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5))[k].ravel() for k in (0, 1)))
    return max(float(np.abs(W[0] @ cp - S[fi][..., :3].reshape(-1, 3)).max()) for fi, cp in enumerate(mesh_cps(table, mesh)))


def tensor_basis(d, us, vs):
    """Tensor Bernstein basis of degree d at the samples (us, vs): value, d/du, d/dv, each (S, (d+1)^2)."""
    Bu, Bv = np.array([_bern(d, x) for x in us]), np.array([_bern(d, x) for x in vs])
    dBu, dBv = np.array([_dbern(d, x) for x in us]), np.array([_dbern(d, x) for x in vs])
    t = lambda a, b: np.einsum('si,sj->sij', a, b).reshape(len(us), -1)
    return t(Bu, Bv), t(dBu, Bv), t(Bu, dBv)


def bound(M=17, K=5):
    """Best unconstrained per-face polynomial patch (tensor degree d, or four bicubic quarters)
    fitted to the exact limit: a floor for any single-patch form of that degree."""
    out = {}
    for name in ['catmark_cube', 'catmark_toroidal_tet', 'catmark_righthanded']:
        V, F = G.load_obj(G._data(f'meshes/{name}.obj')); lim = G.load_limit(name); mesh = G.Mesh(V, F)
        faces = [fi for fi in range(len(F)) if any(mesh.slot(fi, i)[1] != 4 for i in range(4))]
        S = limit_samples(V, F, faces, M, K)
        g = np.linspace(0, 1, M); UU, VV = np.meshgrid(g, g); t8 = np.arange(9) / 8; U8, V8 = np.meshgrid(t8, t8)
        for d, split in [(3, False), (4, False), (3, True)]:
            for wn in (1.0, 10.0):
                D2 = A2 = 0.0
                for a, fi in enumerate(faces):
                    f = F[fi]; h = np.mean([np.linalg.norm(V[f[k]] - V[f[(k + 1) % 4]]) for k in range(4)])
                    P = S[a][..., :3]; N = np.cross(S[a][..., 3:6], S[a][..., 6:9])
                    for jj, ii, j8, i8 in [(0, 0, 0, 0), (0, M - 1, 0, 8), (M - 1, M - 1, 8, 8), (M - 1, 0, 8, 0)]:
                        if np.isnan(P[jj, ii, 0]):
                            P[jj, ii] = lim[fi, j8, i8, :3]; N[jj, ii] = lim[fi, j8, i8, 3:]
                    ok = ~np.isnan(N[..., 0]); N = N / np.linalg.norm(N, axis=-1, keepdims=True)
                    pieces = [(0, 0, 1.0)] if not split else [(0, 0, .5), (.5, 0, .5), (0, .5, .5), (.5, .5, .5)]
                    S8 = np.zeros((9, 9, 3)); N8 = np.zeros((9, 9, 3))
                    for u0, v0, sz in pieces:
                        inside = lambda U, V_: (U >= u0 - 1e-12) & (U <= u0 + sz + 1e-12) & (V_ >= v0 - 1e-12) & (V_ <= v0 + sz + 1e-12)
                        sel = ok & inside(UU, VV)
                        us, vs = (UU[sel] - u0) / sz, (VV[sel] - v0) / sz
                        B, Bu, Bv = tensor_basis(d, us, vs)
                        m = B.shape[1]; Z = np.zeros_like(B)
                        rows = [np.hstack([B if c == x else Z for c in range(3)]) / h for x in range(3)]
                        rows += [math.sqrt(wn) * np.hstack([N[sel][:, c:c + 1] * Bd for c in range(3)]) / h for Bd in (Bu, Bv)]
                        rhs = [P[sel][:, x] / h for x in range(3)] + [np.zeros(len(us))] * 2
                        cp = np.linalg.lstsq(np.vstack(rows), np.concatenate(rhs), rcond=None)[0].reshape(3, m).T
                        s8 = inside(U8, V8); u8, v8 = (U8[s8] - u0) / sz, (V8[s8] - v0) / sz
                        B8, B8u, B8v = tensor_basis(d, u8, v8)
                        S8[s8] = B8 @ cp; N8[s8] = np.cross(B8u @ cp, B8v @ cp)
                    D2 += ((np.linalg.norm(S8 - lim[fi][..., :3], axis=-1) / h * 100) ** 2).sum()
                    A2 += (G.angle_deg(N8, lim[fi][..., 3:]) ** 2).sum()
                key = f"{'2x2 bicubic' if split else f'degree {d}'}, wn {wn:g}"
                out.setdefault(key, {})[name] = (math.sqrt(D2 / (81 * len(F))), math.sqrt(A2 / (81 * len(F))))
                print(f'  {name} {key}: {out[key][name][0]:.3f} / {out[key][name][1]:.3f}', flush=True)
    return out


def sector_probe(table):
    """sectors_verify.py (returned) with this form registered as scheme 'g1cc_quartic': its
    vertex block and sector overrides (docs/boundaries.md: virtual rings, crease/corner v, sharp
    edge points, exact crease tangents for m >= 3) carried over to this form's outputs; at sharp
    positions e and h are the crease curve's, degree elevated (e = v + 3/4 (c1 - v), h = c1 / 2,
    c1 = (2p + q_j) / 3). The per-valence constants are the closed-mesh fit, at n' = 2m."""
    import sectors_verify as SV

    def block(P, n, hook):
        C = table[str(n)]; M = masks(n)
        harm = lambda key, names, m_range, j: sum(C[f'{names[0]}{m}'] * (M[key][j][m - m_range[0]][0] @ P)
                                                  + C[f'{names[1]}{m}'] * (M[key][j][m - m_range[0]][1] @ P) for m in m_range)
        v = hook('v', M['L'] @ P + C['PA'] * (M['wa'] @ P) + C['PB'] * (M['wb'] @ P))
        t = hook('t', [(C['A'] * M['T'][j][0] + C['B'] * M['T'][j][1]) @ P for j in range(n)])
        e = hook('e', [v + t[j] / 4 for j in range(n)])
        h = hook('h', [v / 2 + harm('CH', ('al', 'be'), range(NH + 1), j) for j in range(n)])
        R = {k: hook(f'R{k}', [harm('SH', (f'R{k}q', f'R{k}d'), range(1, NH + 1), j) for j in range(n)]) for k in (1, 2, 3)}
        g = hook('g', [harm('FH', ('gq', 'gd'), range(NH + 1), j) for j in range(n)])
        return dict(v=v, t=t, e=e, h=h, R1=R[1], R2=R[2], R3=R[3], g=g)

    SV.SCHEMES['g1cc_quartic'] = (block, [])
    SV.PER_POS |= {'h', 'R1', 'R2', 'R3', 'g'}
    shipped = SV.overrides

    def overrides(scheme, kind, variant='proposed', m=None):
        if scheme != 'g1cc_quartic':
            return shipped(scheme, kind, variant, m)
        vf = SV.ov_crease_v if kind == 'crease' else SV.ov_corner_v
        c1 = lambda P, j: (2 * P[0] + P[1 + 2 * j]) / 3
        o = {'v': (False, vf), 'e': (True, lambda P, m_, j: vf(P, m_, j) + 0.75 * (c1(P, j) - vf(P, m_, j))),
             'h': (True, lambda P, m_, j: c1(P, j) / 2)}
        if kind == 'crease' and m is not None and m >= 3:
            o['t'] = (False, SV.ov_t_exact_vec)
        return o
    SV.overrides = overrides
    return SV


def sectors(table):
    """Meshes with boundaries and creases: the sector treatment of `sector_probe`. A first probe."""
    SV = sector_probe(table)
    pts = [(SV.T9[ii], SV.T9[jj]) for jj in range(9) for ii in range(9)]
    pts += [(abs(SV.T9[ii] - SV.EPS_CORNER), abs(SV.T9[jj] - SV.EPS_CORNER)) for jj, ii in SV.CORNER_SAMPLES]
    W = basis([p[0] for p in pts], [p[1] for p in pts])

    def ctrl(C):
        """The face's 29 points by `patch`, from the corners' outputs at the face's two
        positions (slot 0 = the edge toward the next corner, 1 = toward the previous one)."""
        corners = [(SimpleNamespace(n=c['n'], v=c['v'], e=[c['e0'], c['e1']], h=[c['h0'], c['h1']],
                                    g=[c['g0'], c['g1']],
                                    R=[{k: c[f'R{k}{x}'] for k in (1, 2, 3)} for x in (0, 1)]), 0)
                   for c in C]
        cp = patch(corners)
        return np.array([cp[k] for k in KEYS])

    print('\n| mesh | g1cc_quartic (probe) | pccm | acc | gregory | gregory_osd |')
    print('|---|---|---|---|---|---|')
    for name in SV.OPEN:
        mesh = SV.Mesh(name, 'sharp'); gt = SV.load_gt(name + '.bin')
        vs = SV.VertexStage(mesh, 'g1cc_quartic'); res = {}
        for f in range(len(mesh.F)):
            G_ = ctrl([vs.corner(f, i) for i in range(4)])
            P, Du, Dv = (W[k] @ G_ for k in range(3))
            N = np.cross(Du[:81], Dv[:81])
            for c, (jj, ii) in enumerate(SV.CORNER_SAMPLES):
                r = 9 * jj + ii
                if np.linalg.norm(N[r]) < 1e-6 * np.linalg.norm(Du[r]) * np.linalg.norm(Dv[r]):
                    N[r] = np.cross(Du[81 + c], Dv[81 + c])
            g8 = gt[f].reshape(81, 6)
            res[f] = (np.linalg.norm(P[:81] - g8[:, :3], axis=1) / mesh.h[f] * 100, SV.angles_deg(N, g8[:, 3:]),
                      all(mesh.corner_regular(x, f) for x in mesh.F[f]))
        cells = [SV.summarise(res)] + [SV.summarise(SV.measure(mesh, gt, sc)) for sc in ('pccm', 'acc', 'gregory', 'gregory_osd')]
        print(f"| {name} | " + ' | '.join(f"{c['rms']:.3f} / {c['nrms']:.3f}" for c in cells) + ' |', flush=True)


def holdout(table):
    """Valences 17..32 on meshes the fit never saw (antiprisms and trapezohedra of n = 18, 24, 30):
    the table against the n = 16 row used for every n > 16, and against `gregory`."""
    rng = np.random.default_rng(99); cases = []
    for n in (18, 24, 30):
        for name, V0, F0 in polyhedra(n):
            if name in ('antiprism', 'trapezohedron'):
                V, F = refine(V0, outward(V0, F0))
                h = np.median([np.linalg.norm(V[f[0]] - V[f[1]]) for f in F])
                V = V @ np.diag(rng.uniform(0.6, 1.6, 3)) + rng.normal(0, 0.10 * h, V.shape)
                mesh = G.Mesh(V, F)
                faces = [fi for fi in range(len(F)) if any(mesh.slot(fi, i)[1] > 16 for i in range(4))]
                cases.append((mesh, faces, limit_samples(V, F, faces, 13, 5)))
    g = np.linspace(0, 1, 13); UU, VV = np.meshgrid(g, g)
    W = basis(UU.ravel(), VV.ravel())
    WG = np.array([[G.gregory_basis(u, v)[c] for v in g for u in g] for c in range(3)])
    saved = dict(G.TABLE); G.TABLE.clear()  # g1cc_verify's Gregory form with no table = `gregory`
    reuse = dict(table, **{str(n): table['16'] for n in range(17, MAX_N + 1)})
    rows = {'table': [[], []], 'n = 16 row for n > 16': [[], []], 'gregory': [[], []]}
    for mesh, faces, S in cases:
        cps = {'table': mesh_cps(table, mesh), 'n = 16 row for n > 16': mesh_cps(reuse, mesh)}
        for a, fi in enumerate(faces):
            f = mesh.F[fi]; h = np.mean([np.linalg.norm(mesh.V[f[k]] - mesh.V[f[(k + 1) % 4]]) for k in range(4)])
            L = S[a].reshape(-1, 9); ok = ~np.isnan(L[:, 0]); NL = np.cross(L[ok, 3:6], L[ok, 6:9])
            for key, Wk, cp in [(k, W, c[fi]) for k, c in cps.items()] + [('gregory', WG, mesh.cps(fi))]:
                rows[key][0].append(np.linalg.norm(Wk[0] @ cp - L[:, :3], axis=1)[ok] / h * 100)
                rows[key][1].append(G.angle_deg(np.cross(Wk[1] @ cp, Wk[2] @ cp)[ok], NL))
    G.TABLE.update(saved)
    print('\nvalences 17..32, held-out antiprisms and trapezohedra (n = 18, 24, 30), RMS dist % / normal °:')
    for key, (D, A) in rows.items():
        D, A = np.concatenate(D), np.concatenate(A)
        print(f'  {key}: {math.sqrt((D ** 2).mean()):.3f} / {math.sqrt((A ** 2).mean()):.3f} (max {D.max():.1f} % / {A.max():.1f}°)')


# ==================================================================== the scheme file (--tess)
# The construction above in the scheme language (codegen/schemes/*.tess): each definition's text is
# written to the file and, in `check_tess`, evaluated by Python as it stands (p[...] read from the
# ring, sum(k, x) over k as an array axis, families as lists whose indices wrap).
QP, DP = '(p[2 * k] - p)', '(p[2 * k + 1] - p)'


def _angle(m, off):
    """2 pi m (k - j + off / 2) / n, off = -1, 0, 1 half steps."""
    if off == 0:
        return f'{2 * m} * pi * (k - j) / n'
    return ('' if m == 1 else f'{m} * ') + f"pi * (2 * (k - j) {'+' if off > 0 else '-'} 1) / n"


def _harm(coef, fn, off, x, ms):
    """coef_m * sum_k fn(angle_m) x_k for m in ms (m = 0: fn = 1), without the 1/n."""
    return [f'{coef}{m} * sum(k, {x.strip("()")})' if m == 0 else f'{coef}{m} * sum(k, {fn}({_angle(m, off)}) * {x})'
            for m in ms]


CONSTS = [('c', 'cos(2 * pi / n)'), ('sigma', '1 / sqrt(4 + cos(pi / n) * cos(pi / n))')]
# (keyword, name, expression) or ('//', '', comment); '\n' marks a line break
VERTEX = [
    ('//', '', 'B-spline face point, used by ordinary quads only.'),
    ('', 'f[j]', '(4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9'),
    ('//', '', 'Catmull-Clark limit point, moved along the two symmetric ring directions.'),
    ('', 'v', '(n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1])) / (n * (n + 5))\n'
     '+ PA * (p - sum(k, p[2 * k]) / n) + PB * (p - sum(k, p[2 * k + 1]) / n)'),
    ('//', '', 'Limit tangent toward q_j, its edge and face parts scaled by A and B; e[j] = v + t[j] / 4.'),
    ('let', 't[j]', 'sum(k,\nA * (1 + cos(pi / n) * sigma) / n * cos(2 * pi * (k - j) / n) * p[2 * k]\n'
     '+ B * sigma / n * cos((2 * (k - j) + 1) * pi / n) * p[2 * k + 1])'),
    ('', 'e[j]', 'v + t[j] / 4'),
    ('//', '', 'hm = 2h, h = v/2 + cosine harmonics about edge j (an edge\'s middle point is\n'
     '(hm_a + hm_b) / 2); harmonic m: (1/n) sum_k cos(2 pi m (k - j + o) / n) (x_k - p),\n'
     'o = 0 for x = q, 1/2 for x = d.'),
    ('', 'hm[j]', 'v + 2 * (' + '\n+ '.join(_harm('al', 'cos', 0, QP, range(NH + 1)) + _harm('be', 'cos', 1, DP, range(NH + 1)))
     + ') / n'),
    ('//', '', 'Sine harmonics about edge j: R_k of the row next to the edge (k = 1, 2, 3).'),
] + [('vector', f'R{r}[j]', '(' + '\n+ '.join(_harm(f'R{r}q', 'sin', 0, 'p[2 * k]', range(1, NH + 1))
                                               + _harm(f'R{r}d', 'sin', 1, 'p[2 * k + 1]', range(1, NH + 1))) + ') / n')
     for r in (1, 2, 3)] + [
    ('//', '', "Cosine harmonics about the face diagonal d_j: the corner's share of the patch centre."),
    ('vector', 'gc[j]', '(' + '\n+ '.join(_harm('gq', 'cos', -1, QP, range(NH + 1)) + _harm('gd', 'cos', 0, DP, range(NH + 1)))
     + ') / n')]
OUTPUTS = ['f', 'v', 'e', 'hm', 'R1', 'R2', 'R3', 'gc']
SECTOR_V = {'crease': '(p[0] + 4 * p + p[2 * m]) / 6', 'corner': 'p'}
SHARP = [('e[j]', '(v + 2 * p + p[2 * j]) / 4'), ('hm[j]', '(2 * p + p[2 * j]) / 3')]
CREASE_T = '''let th = pi / m;
let lam = (cos(th) + 5 + sqrt((cos(th) + 9) * (cos(th) + 1))) / 16;
let wf = 1 / (m * (3 + cos(th)));
let we = 4 * (4 * lam - 1) * wf;
let wc = ((3 * we / 8 + wf / 2) * cos(th / 2) / sin(th / 2)
    + (lam - 0.75) * (we / 2 + 2 * wf) * sin(th))
    / (8 * (lam - 0.75) * (lam - 0.5) - 1);
let across = sum(k, (if k < m { 1 } else { 0 })
        * (wf * (sin(k * th) + sin((k + 1) * th)) * (p[2 * k + 1] - p)
            + we * sin(k * th) * (p[2 * k] - p)))
    + wc * (p[0] + p[2 * m] - 2 * p);
t[j] = if m < 3 {
    t[j]
} else {
    cos(j * th) * (p[0] - p[2 * m]) / 2 + sin(j * th) * across
};'''
BOUNDARY = [
    ('//', '', 'Edge i runs from corner i (its position 0) to corner i+1 (its position 1): its quartic\n'
     'boundary is v(i), e(i, 0), mid[i], e(i + 1, 1), v(i + 1). Both faces of the edge add the\n'
     'same two outputs, so the shared curve is the same bits.'),
    ('', 'mid[i]', '(hm(i, 0) + hm(i + 1, 1)) * 0.5'),
    ('out', 'p[i]', 'v(i)'), ('out', 'ep[i]', 'e(i, 0)'), ('out', 'em[i]', 'e(i, 1)'), ('out', 'm[i]', 'mid[i]')]
ORDINARY = BOUNDARY + [
    ('//', '', 'The interior from the cubic net (v, e3 = (4e - v) / 3, f), degree-elevated.'),
    ('', 'b11[i]', '(4 * e(i, 0) + 4 * e(i, 1) - v(i) + 9 * f(i, 0)) / 16'),
    ('out', 'fp[i]', 'b11[i]'), ('out', 'fm[i]', 'b11[i]'),
    ('out', 'g[i]', '(4 * e(i, 0) - v(i) + 4 * e(i + 1, 1) - v(i + 1)\n+ 9 * f(i, 0) + 9 * f(i + 1, 0)) / 24'),
    ('out', 'center', 'sum(k, f(k, 0)) / 4')]
EXTRAORDINARY = BOUNDARY + [
    ('//', '', 'The row next to edge i: b_k1 = P_k + rho_k / 2 + R_k(i, 0) - R_{4-k}(i + 1, 1), with\n'
     'rho_k = (4 - k)/4 l0 tau_k + k/4 l1 tau_{k-1}, tau_k = P_{k+1} - P_k, l0 = 2 c(i) and\n'
     'l1 = -2 c(i + 1): fp[i] is b_11 of edge i, g[i] its b_21, fm[i] the b_31 of edge i - 1.'),
    ('out', 'fp[i]', 'e(i, 0) + (3 * c(i) * (mid[i] - e(i, 0)) - c(i + 1) * (e(i, 0) - v(i))) / 4\n'
     '+ R1(i, 0) - R3(i + 1, 1)'),
    ('out', 'g[i]', 'mid[i] + (c(i) * (e(i + 1, 1) - mid[i]) - c(i + 1) * (mid[i] - e(i, 0))) / 2\n'
     '+ R2(i, 0) - R2(i + 1, 1)'),
    ('out', 'fm[i]', 'e(i, 1) + (c(i - 1) * (v(i) - e(i, 1)) - 3 * c(i) * (e(i, 1) - mid[i - 1])) / 4\n'
     '+ R3(i - 1, 0) - R1(i, 1)'),
    ('out', 'center', 'sum(k, v(k) + gc(k, 0)) / 4')]
HEADER = f'''g1cc: G¹ biquartic Gregory patches fitted to the Catmull-Clark limit (issue 20; docs/g1cc.md
round 6, "The form"). Per vertex: v near the limit point, edge points e in the exact limit
tangent plane, hm = 2h (the quartic boundary's middle point is (hm_a + hm_b) / 2, one output
from each end), the antisymmetric vectors R1..R3 of the row next to an edge, and gc, the
corner's share of the patch centre: 38 constants per valence, fitted by one linear
least-squares solve against the exact limit (docs/verify/g1cc_quartic_table.json, wn = {FIT_WN:g}).
G¹ for every value of the constants; ordinary quads are the bicubic B-spline, degree-elevated.
Generated by `python3 docs/verify/g1cc_quartic_verify.py --tess codegen/schemes/g1cc.tess`;
do not edit by hand.'''


def _defs(defs, ind):
    out = []
    for kw, name, text in defs:
        if kw == '//':
            out += [ind + '// ' + s for s in text.split('\n')]
            continue
        out += (ind + (kw + ' ' if kw else '') + f'{name} = {text};').replace('\n', '\n' + ind + '    ').split('\n')
    return out


def _const(name, vals):
    """`const NAME = if n == 3 { .. } else if .. else { <last row> };`, wrapped at 100 columns."""
    ns = sorted(vals)
    parts = [f'if n == {n} {{ {vals[n]!r} }}' for n in ns[:-1]] + [f'{{ {vals[ns[-1]]!r} }};']
    lines, cur = [], f'    const {name} ='
    for k, s in enumerate(parts):
        s = s if k == 0 else 'else ' + s
        if len(cur) + len(s) + 1 > 100:
            lines.append(cur); cur = '       '
        cur += ' ' + s
    return lines + [cur]


def write_tess(table, path):
    ns = sorted(map(int, table))
    assert ns == list(range(3, MAX_N + 1))
    L = ['/// ' + s for s in HEADER.split('\n')] + ['scheme g1cc {', '    facet quad;', '']
    L += [f'    const {name} = {text};' for name, text in CONSTS]
    L += [f'    // The fitted constants of valences 3..{MAX_N}; valences above {MAX_N} take the n = {MAX_N} row.']
    for nm in NAMES:
        L += _const(nm, {n: table[str(n)][nm] for n in ns})
    L += ['', '    vertex {'] + _defs(VERTEX, ' ' * 8) + ['    }', '']
    L += ['    // Crease and corner vertices (docs/boundaries.md), as the --sectors probe of docs/g1cc.md',
          "    // round 6: the crease and corner v; at the sharp edges the crease curve's cubic Bézier points",
          '    // (v, c1 = (2p + q_j) / 3) degree-elevated, e = v + 3/4 (c1 - v) and hm = 2h = c1; for creases',
          '    // of m ≥ 3 faces the exact limit tangents t = T_j of `gregory` (e = v + T_j / 4). Every other',
          "    // output is the scheme's own on the virtual ring, with the constants of n' = 2m."]
    for kind in ('crease', 'corner'):
        L += [f'    sector {kind} {{', f'        v = {SECTOR_V[kind]};']
        L += [f'        sharp {name} = {text};' for name, text in SHARP]
        L += ['        ' + s if s else s for s in CREASE_T.split('\n')] if kind == 'crease' else []
        L += ['    }']
    for cls, defs in (('ordinary', ORDINARY), ('extraordinary', EXTRAORDINARY)):
        L += ['', f'    patch {cls}: gregory4 {{'] + _defs(defs, ' ' * 8) + ['    }']
    L += ['}']
    with open(path, 'w') as fh:
        fh.write('\n'.join(L) + '\n')
    print(f'wrote {path} ({len(L)} lines)')


class _Fam(list):
    """A family over ring positions or corners: its indices wrap."""

    def __getitem__(s, i): return list.__getitem__(s, i % len(s))


class _Ring:
    """p[i]: ring slot 1 + i mod 2n; an array of indices gives one row each."""

    def __init__(s, P): s.P = P
    def __getitem__(s, i): return s.P[1 + np.ravel(i) % (len(s.P) - 1)] if np.ndim(i) else s.P[1 + i % (len(s.P) - 1)]


@functools.lru_cache(None)
def _code(text):
    return compile(re.sub(r'\bp\[', 'ring[', ' '.join(text.split())), '<tess>', 'eval')


def _eval(text, ns):
    return eval(_code(text), ns)


def _consts(table, n):
    C = dict(table[str(min(n, MAX_N))], n=n, pi=math.pi, cos=np.cos, sin=np.sin, sqrt=np.sqrt,
             sum=lambda _, x: x.sum(0))
    for name, text in CONSTS:
        C[name] = _eval(text, C)
    return C


def _vertex(P, n, C, over=None, m=None):
    """Every vertex definition at every ring position; over: name -> (sharp, text or fn(P, m, j))."""
    ns = dict(C, p=P[0], ring=_Ring(P), k=np.arange(n)[:, None], m=m)
    for _, name, text in (d for d in VERTEX if d[0] != '//'):
        key = name.split('[')[0]
        sharp, alt = (over or {}).get(key, (False, None))

        def one(j):
            ns['j'] = j
            if alt is None or (sharp and j not in (0, m)):
                return _eval(text, ns)
            return alt(P, m, j) if callable(alt) else _eval(alt, ns)
        ns[key] = _Fam(one(j) for j in range(n)) if '[' in name else one(None)
    return ns


def _tess_cps(defs, corners):
    """The 29 points (KEYS order) by a patch block's texts; corners: [(vertex defs, n, j)] CCW."""
    def reader(name):
        def get(i, o=0):
            if np.ndim(i):
                return np.array([get(x, o) for x in np.ravel(i)])
            V, n, ja = corners[i % 4]
            return V[name][ja + o] if isinstance(V[name], _Fam) else V[name]
        return get
    ns = {name: reader(name) for name in OUTPUTS + ['c']}
    ns.update(k=np.arange(4), sum=lambda _, x: x.sum(0))
    out = {}
    for kw, name, text in defs:
        if kw != '//':
            val = _Fam(_eval(text, dict(ns, i=i)) for i in range(4)) if '[' in name else _eval(text, ns)
            (out if kw == 'out' else ns)[name.split('[')[0]] = val
    hv = lambda i: 'h' if i % 2 == 0 else 'v'
    cp = {(2, 2): out['center']}
    for i in range(4):
        cp.update({_slot(i, 0, 0): out['p'][i], _slot(i, 1, 0): out['ep'][i], _slot(i, 2, 0): out['m'][i],
                   _slot(i - 1, 3, 0): out['em'][i], (hv(i), _slot(i, 1, 1)): out['fp'][i],
                   _slot(i, 2, 1): out['g'][i], (hv(i - 1), _slot(i - 1, 3, 1)): out['fm'][i]})
    assert len(cp) == len(KEYS)
    return np.array([cp[key] for key in KEYS])


def check_tess(table):
    """The written texts against `patch` (closed meshes) and the --sectors probe (sector rows)."""
    rng = np.random.default_rng(2026); lay = table_layout(table); ok = True
    ref = lambda cs: np.array([x.c for x in map(patch(cs).get, KEYS)])
    worst = 0.0; faces = 0
    for n0 in range(3, MAX_N + 1):
        for _ in range(4):
            vals = [int(n) for n in np.roll([n0] + list(rng.integers(3, 9, 3)), faces)]
            Ps = [rng.normal(0, 1, (2 * n + 1, 3)) for n in vals]; js = [int(rng.integers(n)) for n in vals]
            mine = _tess_cps(EXTRAORDINARY, [(_vertex(P, n, _consts(table, n)), n, j) for P, n, j in zip(Ps, vals, js)])
            worst = max(worst, float(np.abs(mine - ref([(Vertex(lay, P, n), j) for P, n, j in zip(Ps, vals, js)])).max()))
            faces += 1
    print(f'--tess: extraordinary class vs patch(), {faces} faces of random rings (valences 3..{MAX_N} at one corner, '
          f'3..8 at the others): max |diff| {worst:.2e}')
    ok &= worst < 1e-12
    V, F = torus_grid(seed=5); mesh = G.Mesh(V, F); worst = 0.0
    for fi in range(len(F)):
        cs = [mesh.slot(fi, i) for i in range(4)]
        Ps = [mesh.V[[x] + mesh.rings[x]] for x, _, _ in cs]
        mine = _tess_cps(ORDINARY, [(_vertex(P, 4, _consts(table, 4)), 4, j) for P, (_, _, j) in zip(Ps, cs)])
        worst = max(worst, float(np.abs(mine - ref([(Vertex(lay, P, 4), j) for P, (_, _, j) in zip(Ps, cs)])).max()))
    print(f'--tess: ordinary class vs patch(), {len(F)} faces of a noisy regular torus: max |diff| {worst:.2e}')
    ok &= worst < 1e-12
    SV = sector_probe(table); worst = 0.0
    for kind in ('crease', 'corner'):
        for m in range(1, MAX_N // 2 + 1):
            n, rows = SV.virtual_valence(m), SV.sector_rows('g1cc_quartic', kind, m)
            over = dict({'v': (False, SECTOR_V[kind])}, **{nm[:-3]: (True, tx) for nm, tx in SHARP})
            if kind == 'crease' and m >= 3:
                over['t'] = (False, SV.ov_t_exact_vec)
            D = _vertex(SV.virtual_ring(m), n, _consts(table, n), over, m)
            for a, b, s in [('v', 'v', 1), ('e', 'e', 1), ('hm', 'h', 2), ('R1', 'R1', 1), ('R2', 'R2', 1),
                            ('R3', 'R3', 1), ('gc', 'g', 1)]:
                x = np.array([D[a][j] for j in range(m + 1)]) if a != 'v' else D[a]
                worst = max(worst, float(np.abs(x - s * rows[b]).max()))
    same_t = ' '.join(CREASE_T.split()) in ' '.join(open(os.path.join(HERE, '..', '..', 'codegen', 'schemes',
                                                                       'gregory.tess')).read().split())
    print(f'--tess: sector rows vs the --sectors probe (crease and corner, m = 1..{MAX_N // 2}): max |diff| {worst:.2e}; '
          f"crease tangents = gregory.tess's text: {'yes' if same_t else 'NO'}")
    ok &= worst < 1e-12 and same_t
    print('--tess checks:', 'PASS' if ok else 'FAIL')
    return ok


def golden(table, meshes):
    out = dict(scheme='g1cc (round 6, biquartic Gregory)', note='float64; control points in KEYS order '
               '(grid (a, b) with a along u, then the twist pairs (h = horizontal-edge point, v = vertical)); '
               'eval: position, dPdu, dPdv (exact), unit normal', keys=[str(k) for k in KEYS], table=table, cases=[])
    want = {}
    for name, mesh in meshes.items():
        for fi in range(len(mesh.F)):
            ns = tuple(mesh.slot(fi, i)[1] for i in range(4))
            for n in ns:
                if n != 4 and n not in want:
                    want[n] = (name, fi, ns)
    for n in sorted(want):
        name, fi, ns = want[n]
        cp = mesh_cps(table, meshes[name])[fi]
        ev = []
        for u, v in [(0.0, 0.0), (0.25, 0.0), (0.3, 0.6), (0.5, 0.5), (0.9, 0.15), (1.0, 1.0)]:
            W = basis([u], [v]); S, Su, Sv = (W[k] @ cp for k in range(3))
            Nn = np.cross(Su, Sv)
            ev.append(dict(u=u, v=v, position=S[0].tolist(), dPdu=Su[0].tolist(), dPdv=Sv[0].tolist(),
                           normal=(Nn / np.linalg.norm(Nn)).tolist()[0]))
        out['cases'].append(dict(mesh=name, face=fi, valences=list(ns), control_points=cp.tolist(), eval=ev))
    return out


def main():
    if '--tess' in sys.argv:
        table = json.load(open(TABLE_PATH))['table']
        write_tess(table, sys.argv[sys.argv.index('--tess') + 1])
        sys.exit(0 if check_tess(table) else 1)
    if '--fit' in sys.argv:
        table = fit()
        json.dump(dict(note=f'g1cc round 6 constants, fitted by g1cc_quartic_verify.py --fit (wn = {FIT_WN:g})',
                       names=NAMES, table=table), open(TABLE_PATH, 'w'), indent=1)
        print('table written to', TABLE_PATH)
    if '--bound' in sys.argv:
        bound()
    table = json.load(open(TABLE_PATH))['table']
    rng = np.random.default_rng(2026); ok = True
    lp, ln, cnt = check_limit()
    print(f'exact-limit evaluator vs cc_limit, {cnt} samples (cube, toroidal_tet): position {lp:.1e} of the mesh size, normal {ln:.1e} deg')
    ok &= lp < 1e-6 and ln < 1e-4
    aff = check_affine(rng, table)
    print(f'affine invariance (every control point moves with a translation), n = 3..{MAX_N}: {aff:.2e}')
    ok &= aff < 1e-11
    reg = check_regular(table)
    print(f'regular faces = uniform bicubic B-spline: max position error {reg:.2e}')
    ok &= reg < 1e-12
    ga, gp = check_g1_random(rng)
    print(f'G1 with random tables, random rings of valences n0, n1 = 3..{MAX_N}: max normal angle {ga:.2e} deg, max gap {gp:.2e}')
    ok &= ga < 1e-8 and gp < 1e-12
    meshes = {}
    print('\n| mesh | RMS dist % | target | max dist % | RMS normal ° | target | max normal ° | G1 edge max ° | met |')
    print('|---|---|---|---|---|---|---|---|---|')
    for name in CLOSED:
        mesh, r = measure(table, name); meshes[name] = mesh
        ea, ep = edge_check(mesh_cps(table, mesh), mesh)
        td, tn = G.TARGETS[name]
        met = r['rms_d'] <= td and r['rms_n'] <= tn
        print(f"| {name} | {r['rms_d']:.4f} | {td} | {r['max_d']:.4f} | {r['rms_n']:.4f} | {tn} | {r['max_n']:.4f} | {ea:.1e} | {'yes' if met else 'NO'} |")
        ok &= ea < 1e-8 and ep < 1e-12
    if '--sectors' in sys.argv:
        sectors(table)
    if '--holdout' in sys.argv:
        holdout(table)
    if '--golden' in sys.argv:
        path = sys.argv[sys.argv.index('--golden') + 1]
        json.dump(golden(table, meshes), open(path, 'w'), indent=1)
        print('golden values written to', path)
    print('structural checks:', 'PASS' if ok else 'FAIL')
    sys.exit(0 if ok else 1)


if __name__ == '__main__':
    main()

//! Sectors of crease and corner vertices (docs/boundaries.md §3): the
//! stencil rows of a sector of `m` faces over its partial ring
//! `[p, q_0, d_0, …, d_{m−1}, q_m]`.
//!
//! The rows are the scheme's own vertex definitions evaluated on a *virtual
//! ring* of valence `n'(m)` whose missing points are phantom points — fixed
//! affine combinations of the partial ring — except where the scheme's
//! `sector` block overrides a definition with the shared crease data. At
//! `m = 2` (crease) and `m = 1` (corner) the phantom points are exactly the
//! extrapolation that makes the bicubic B-spline reproduce Catmull-Clark's
//! boundary and crease rules (spec/boundary.md §4.2), so those sectors are
//! exact for every scheme that is the B-spline at valence 4.

use super::*;

/// What cuts a vertex's ring: a crease (two sharp edges, limit on the
/// crease curve) or a corner (the vertex is interpolated).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SectorKind {
    Crease,
    Corner,
}

impl SectorKind {
    /// Every kind, in table order (`block = kind · SECTOR_MAX_FACES + m − 1`).
    pub const ALL: [SectorKind; 2] = [SectorKind::Crease, SectorKind::Corner];

    pub fn name(self) -> &'static str {
        match self {
            SectorKind::Crease => "crease",
            SectorKind::Corner => "corner",
        }
    }

    /// Position in [`SectorKind::ALL`].
    pub fn index(self) -> u32 {
        match self {
            SectorKind::Crease => 0,
            SectorKind::Corner => 1,
        }
    }
}

/// One definition of a `sector` block.
#[derive(Clone, Debug)]
pub struct SectorOverride {
    /// The vertex definition it replaces.
    pub def: usize,
    /// `sharp`: only at the sector's sharp edges (positions 0 and m).
    pub sharp: bool,
    pub expr: Sym,
    pub span: Span,
}

/// A resolved `sector KIND { … }` block.
#[derive(Clone, Debug)]
pub struct SectorBlock {
    pub kind: SectorKind,
    pub overrides: Vec<SectorOverride>,
}

/// Largest sector (in faces) the table holds at this maximum valence: a
/// crease sector of `m` faces is evaluated at virtual valence `2m`.
pub fn max_sector_faces(max_valence: u32) -> u32 {
    max_valence / 2
}

/// Virtual valence of a sector of `m ≥ 1` faces: 4 for one face (the tensor
/// extrapolation of a corner face), `2m` otherwise (the sector reflected
/// through its centre).
pub fn virtual_valence(m: u32) -> u32 {
    if m == 1 {
        4
    } else {
        2 * m
    }
}

/// Slot of `p` in a partial ring.
const P: u64 = 0;
/// Slot of `q_i` in a partial ring.
fn q(i: u32) -> u64 {
    1 + 2 * i as u64
}
/// Slot of `d_i` in a partial ring.
fn d(i: u32) -> u64 {
    2 + 2 * i as u64
}

fn point(terms: &[(u64, f64)]) -> Value {
    let mut m = BTreeMap::new();
    for &(k, w) in terms {
        *m.entry(k).or_insert(0.0) += w;
    }
    Value::Point(m)
}

/// Virtual-ring slot `slot` (1 + 2j = edge Q_j, 2 + 2j = diagonal D_j,
/// j < n'(m)) of a sector of `m` faces, as an affine combination of the
/// partial ring's slots (docs/boundaries.md §3).
pub fn phantom_point(m: u32, slot: u32) -> Value {
    let j = (slot - 1) / 2;
    let edge = slot % 2 == 1; // slot - 1 even: an edge point Q_j
    if m == 1 {
        // Face (p, q0, d0, q1) and its three mirror images.
        return match (edge, j) {
            (true, 0) => point(&[(q(0), 1.0)]),
            (false, 0) => point(&[(d(0), 1.0)]),
            (true, 1) => point(&[(q(1), 1.0)]),
            (false, 1) => point(&[(q(1), 2.0), (d(0), -1.0)]),
            (true, 2) => point(&[(P, 2.0), (q(0), -1.0)]),
            (false, 2) => point(&[(P, 4.0), (q(0), -2.0), (q(1), -2.0), (d(0), 1.0)]),
            (true, _) => point(&[(P, 2.0), (q(1), -1.0)]),
            (false, _) => point(&[(q(0), 2.0), (d(0), -1.0)]),
        };
    }
    if edge {
        if j <= m {
            point(&[(q(j), 1.0)])
        } else {
            point(&[(P, 2.0), (q(j - m), -1.0)])
        }
    } else if j < m {
        point(&[(d(j), 1.0)])
    } else if j == m {
        point(&[(q(m), 2.0), (d(m - 1), -1.0)])
    } else if j == 2 * m - 1 {
        point(&[(q(0), 2.0), (d(0), -1.0)])
    } else {
        point(&[(P, 2.0), (d(j - m), -1.0)])
    }
}

/// Evaluates a scheme's vertex definitions for one sector kind and size on
/// the virtual ring, with the `sector` block's overrides.
pub(super) struct SectorEnv<'a> {
    scheme: &'a Scheme,
    block: Option<&'a SectorBlock>,
    m: u32,
    n: u32,
    consts: Vec<f64>,
    /// Values by (definition, ring position, inherited): `inherited` is the
    /// scheme's own definition where an override replaces it.
    memo: std::cell::RefCell<BTreeMap<(usize, u32, bool), Value>>,
}

impl<'a> SectorEnv<'a> {
    pub(super) fn new(scheme: &'a Scheme, kind: SectorKind, m: u32) -> Self {
        let n = virtual_valence(m);
        SectorEnv {
            scheme,
            block: scheme.sectors.iter().find(|b| b.kind == kind),
            m,
            n,
            consts: scheme.const_values(n),
            memo: Default::default(),
        }
    }

    fn expr(&self, def: usize, j: u32) -> &'a Sym {
        let sharp_edge = j == 0 || j == self.m;
        let chosen = self.block.and_then(|b| {
            // A `sharp` override wins at the sharp edges; a plain one
            // everywhere else (and at the sharp edges when there is no
            // `sharp` one).
            let at = |sharp: bool| {
                b.overrides
                    .iter()
                    .find(|o| o.def == def && o.sharp == sharp)
            };
            if sharp_edge {
                at(true).or_else(|| at(false))
            } else {
                at(false)
            }
        });
        match chosen {
            Some(o) => &o.expr,
            None => &self.scheme.vertex[def].expr,
        }
    }

    /// Definition `def` at position `j`: with the block's override, or the
    /// scheme's own expression when `inherited` (an override reading the
    /// definition it replaces; that expression reads only earlier
    /// definitions, which still see their overrides).
    fn value(&self, def: usize, j: u32, inherited: bool) -> Value {
        if let Some(v) = self.memo.borrow().get(&(def, j, inherited)) {
            return v.clone();
        }
        let mut vars = Vec::new();
        sym::set_var(&mut vars, SECTOR_VAR, j as f64);
        let expr = if inherited {
            &self.scheme.vertex[def].expr
        } else {
            self.expr(def, j)
        };
        let v = sym::eval(expr, self, &mut vars);
        self.memo
            .borrow_mut()
            .insert((def, j, inherited), v.clone());
        v
    }

    fn position(&self, index: Option<i64>) -> u32 {
        index
            .map(|j| j.rem_euclid(self.n as i64) as u32)
            .unwrap_or(0)
    }

    /// Weights of output `def` at ring position `j` over the 2m + 2 slots.
    pub(super) fn row(&self, def: usize, j: u32) -> Vec<f64> {
        let mut row = vec![0.0; 2 * self.m as usize + 2];
        for (slot, w) in self.value(def, j, false).point() {
            row[slot as usize] += w;
        }
        row
    }
}

impl Env for SectorEnv<'_> {
    fn valence(&self) -> f64 {
        self.n as f64
    }
    fn sum_range(&self) -> u32 {
        self.n
    }
    fn konst(&self, k: usize) -> f64 {
        self.consts.get(k).copied().unwrap_or(f64::NAN)
    }
    fn center(&self) -> Value {
        Value::unit(P)
    }
    fn ring(&self, idx: i64) -> Value {
        phantom_point(self.m, 1 + idx.rem_euclid(2 * self.n as i64) as u32)
    }
    fn def(&self, def: usize, index: Option<i64>) -> Value {
        self.value(def, self.position(index), false)
    }
    fn inherited(&self, def: usize, index: Option<i64>) -> Value {
        self.value(def, self.position(index), true)
    }
    fn sector_faces(&self) -> f64 {
        self.m as f64
    }
}

impl Scheme {
    /// Every exported vertex-stage row of a sector of `m` faces, in table
    /// order, as `(output def, ring position j, weights over the partial
    /// ring [p, q_0, d_0, …, q_m])`: `m + 1` rows (j = 0 … m) per family,
    /// one per single output.
    pub fn sector_rows(&self, kind: SectorKind, m: u32) -> Vec<(usize, u32, Vec<f64>)> {
        let env = SectorEnv::new(self, kind, m);
        let mut out = Vec::new();
        for (i, d) in self.outputs() {
            let count = if d.indexed { m + 1 } else { 1 };
            for j in 0..count {
                out.push((i, j, env.row(i, j)));
            }
        }
        out
    }

    /// Rows of a sector block of `m` faces: `a·(m + 1) + b`.
    pub fn rows_per_sector(&self, m: u32) -> u32 {
        let (a, b) = self.rows_linear();
        a * (m + 1) + b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phantom_points_are_affine_and_exact_at_the_regular_sizes() {
        for m in 1..=16 {
            for slot in 1..=2 * virtual_valence(m) {
                let w: f64 = phantom_point(m, slot).point().values().sum();
                assert!((w - 1.0).abs() < 1e-15, "m={m} slot={slot}: {w}");
            }
        }
        // A planar unit grid around p = 0: every phantom lands on the grid
        // point of the virtual ring (the regular crease and corner).
        let grid = |m: u32, pts: &[(f64, f64)]| {
            let n = virtual_valence(m);
            (1..=2 * n)
                .map(|s| {
                    let v = phantom_point(m, s).point();
                    v.iter().fold((0.0, 0.0), |acc, (k, w)| {
                        let (x, y) = pts[*k as usize];
                        (acc.0 + w * x, acc.1 + w * y)
                    })
                })
                .collect::<Vec<_>>()
        };
        let full = [
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (-1.0, 1.0),
            (-1.0, 0.0),
            (-1.0, -1.0),
            (0.0, -1.0),
            (1.0, -1.0),
        ];
        let crease = [
            (0.0, 0.0),
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (-1.0, 1.0),
            (-1.0, 0.0),
        ];
        let corner = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        for (m, pts) in [(2, &crease[..]), (1, &corner[..])] {
            for (got, want) in grid(m, pts).iter().zip(&full) {
                assert!((got.0 - want.0).abs() < 1e-15 && (got.1 - want.1).abs() < 1e-15);
            }
        }
    }
}

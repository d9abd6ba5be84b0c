//! Patch forms: the small fixed set of surface representations a scheme's
//! patch stage can produce, and what their control points mean.
//!
//! A form names its per-corner control-point slots (what a scheme's `out`
//! statements must fill), how they are stored, and which stored points (four for a cubic, five for a quartic)
//! make up the boundary curve of each edge (the curve the shared edge
//! evaluator works on). How a form is *evaluated* is lowered into the Plan by
//! [`crate::lower`]; printers never see a form.

/// A patch representation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Form {
    /// Bicubic Bézier patch, 16 points `G[k][l]` stored row-major `4k + l`
    /// (k = u-index), as in `spec/regular.md` §3/§5.
    Bicubic,
    /// PCCM c-patch: 24 coefficients stored `6i + {v, t0, t1, b211, b121, b112}`,
    /// evaluated as four quartic triangles (`spec/pccm.md` §4.3–§5.2).
    CPatch,
    /// ACC (`spec/acc.md`): a bicubic geometry patch (16 points, stored like
    /// [`Form::Bicubic`]) plus the two tangent patches U (3×4) and V (4×3)
    /// whose cross product is the shading normal. The 24 tangent coefficients
    /// are declared per corner in the corner's own frame (`a` toward
    /// `v_{i+1}`, `b` toward `v_{i-1}`, derivatives `D_a`, `D_b`) and stored
    /// `16 + 6i + {da00, da01, da10, da11, db00, db10}`; evaluation maps them
    /// back to U, V with the corner's signs (see [`Form::acc_tangent_slot`]).
    Acc,
    /// Gregory patch (`spec/gregory.md`): 20 points stored `5i + {p, ep, em,
    /// fp, fm}` (OpenSubdiv order), interior points blended rationally.
    Gregory,
    /// Biquartic Gregory patch (`docs/g1cc.md` round 6): a 5×5 Bézier net
    /// whose four twist points are rationally blended pairs, as in
    /// [`Form::Gregory`]: 29 points stored `7i + {p, ep, em, m, fp, fm, g}`
    /// and the centre `center` at 28. Per corner i: the corner `p`, the
    /// boundary points next to it toward corner i+1 (`ep`) and i−1 (`em`),
    /// the middle point `m` of edge i (i → i+1), the twist point serving
    /// edge i (`fp`) and edge i−1 (`fm`), and the middle point `g` of the
    /// row next to edge i. Its boundary curves are quartics (five points):
    /// the shared edge evaluator is the quartic one.
    Gregory4,
    /// Cubic Bézier triangle with a quadratic normal field (`spec/pn.md`):
    /// per corner i the vertex point `b`, the edge points next to it toward
    /// corner i+1 (`bn`) and i−1 (`bp`), the normal coefficient `n` and the
    /// mid-edge normal coefficient `nm` of edge i → i+1, stored `5i + slot`;
    /// the centre `center` at 15. The normal field is the factor-free
    /// quadratic `Σ n_i w_i² + Σ nm_i w_i w_{i+1}` (pn.md §2), normalised.
    TriCubic,
}

/// What a control-point slot holds: its stencil weights sum to 1 (a point)
/// or to 0 (a vector, e.g. an ACC tangent coefficient).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlotKind {
    Point,
    Vector,
}

/// Where an ACC tangent coefficient of the corner frame lands in U or V.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TangentSlot {
    /// `false`: U (3×4, index `[a][b]` with a along u); `true`: V (4×3).
    pub in_v: bool,
    pub a: usize,
    pub b: usize,
    /// The stored corner-frame value is `sign ×` the U/V coefficient.
    pub negate: bool,
}

impl Form {
    pub fn from_name(name: &str) -> Option<Form> {
        match name {
            "bicubic" => Some(Form::Bicubic),
            "cpatch" => Some(Form::CPatch),
            "acc" => Some(Form::Acc),
            "gregory" => Some(Form::Gregory),
            "gregory4" => Some(Form::Gregory4),
            "tri_cubic" => Some(Form::TriCubic),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Form::Bicubic => "bicubic",
            Form::CPatch => "cpatch",
            Form::Acc => "acc",
            Form::Gregory => "gregory",
            Form::Gregory4 => "gregory4",
            Form::TriCubic => "tri_cubic",
        }
    }

    /// Every form name, for error messages.
    pub const NAMES: &'static str =
        "`bicubic`, `cpatch`, `acc`, `gregory`, `gregory4` or `tri_cubic`";

    /// Corners of the facet the form covers (4 for quads, 3 for triangles).
    pub fn sides(self) -> usize {
        match self {
            Form::TriCubic => 3,
            _ => 4,
        }
    }

    /// Slots that exist once per patch (`out NAME = …;`), stored after the
    /// per-corner ones.
    pub fn single_slots(self) -> &'static [&'static str] {
        match self {
            Form::TriCubic | Form::Gregory4 => &["center"],
            _ => &[],
        }
    }

    /// Storage index of single slot `k`.
    pub fn single_index(self, k: usize) -> usize {
        self.sides() * self.slots().len() + k
    }

    /// Per-corner slots a scheme must define with `out SLOT[i] = …`.
    pub fn slots(self) -> &'static [&'static str] {
        match self {
            // Corner-local Bézier indices: b10 is one step toward v_{i+1},
            // b01 one step toward v_{i-1}, b11 the interior point.
            Form::Bicubic => &["b00", "b10", "b01", "b11"],
            Form::CPatch => &["v", "t0", "t1", "b211", "b121", "b112"],
            // Geometry as Bicubic; then D_a[0][0], D_a[0][1], D_a[1][0],
            // D_a[1][1], D_b[0][0], D_b[1][0] of the corner frame (first
            // index along a, second along b).
            Form::Acc => &[
                "b00", "b10", "b01", "b11", "da00", "da01", "da10", "da11", "db00", "db10",
            ],
            Form::Gregory => &["p", "ep", "em", "fp", "fm"],
            Form::Gregory4 => &["p", "ep", "em", "m", "fp", "fm", "g"],
            Form::TriCubic => &["b", "bn", "bp", "n", "nm"],
        }
    }

    /// Whether slot `slot` is a point (weights sum to 1) or a vector (0).
    pub fn slot_kind(self, slot: usize) -> SlotKind {
        match self {
            Form::Acc if slot >= 4 => SlotKind::Vector,
            Form::TriCubic if slot >= 3 => SlotKind::Vector,
            _ => SlotKind::Point,
        }
    }

    /// ACC: where tangent slot `slot` (4..10) of corner `corner` lands.
    ///
    /// Corner k's frame is `a` = toward v_{k+1}, `b` = toward v_{k-1}:
    /// corner 0 (a, b) = (u, v), 1 = (v, −u), 2 = (−u, −v), 3 = (−v, u). So
    /// `D_a` is U, V, −U, −V and `D_b` is V, −U, −V, U at corners 0..3, and a
    /// corner-frame index `[α][β]` (α along a) maps to the grid by the same
    /// rotation as the geometry points.
    pub fn acc_tangent_slot(corner: usize, slot: usize) -> TangentSlot {
        // (is D_b, α, β) of the slot in the corner frame.
        let (is_db, al, be) = match slot {
            4 => (false, 0, 0),
            5 => (false, 0, 1),
            6 => (false, 1, 0),
            7 => (false, 1, 1),
            8 => (true, 0, 0),
            _ => (true, 1, 0),
        };
        // Degrees along (a, b): D_a is quadratic in a, cubic in b; D_b the reverse.
        let (da, db) = if is_db { (3, 2) } else { (2, 3) };
        // Grid position (x along u, y along v) of corner-frame index (α, β):
        // corner 0 (α, β); 1 (d_b−β, α); 2 (d_a−α, d_b−β); 3 (β, d_a−α),
        // where the u- and v-degrees follow which of U/V the patch is.
        let k = corner % 4;
        // Which global patch: D_a is U at corners 0, 2 and V at 1, 3.
        let in_v = (k % 2 == 1) != is_db;
        let (x, y) = match k {
            0 => (al, be),
            1 => (db - be, al),
            2 => (da - al, db - be),
            _ => (be, da - al),
        };
        // D_a = U, V, −U, −V; D_b = V, −U, −V, U.
        let negate = if is_db { k == 1 || k == 2 } else { k >= 2 };
        TangentSlot {
            in_v,
            a: x,
            b: y,
            negate,
        }
    }

    /// Number of stored control points.
    pub fn num_points(self) -> usize {
        self.sides() * self.slots().len() + self.single_slots().len()
    }

    /// Storage index of slot `slot` of corner `corner`.
    pub fn storage_index(self, corner: usize, slot: usize) -> usize {
        match self {
            Form::Bicubic => {
                // Corner k of the quad sits at grid (0,0), (3,0), (3,3), (0,3);
                // "toward v_{k+1}" is +u, +v, -u, -v and "toward v_{k-1}" is
                // +v, -u, -v, +u (regular.md §3).
                const CORNER: [(i32, i32); 4] = [(0, 0), (3, 0), (3, 3), (0, 3)];
                const NEXT: [(i32, i32); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];
                const PREV: [(i32, i32); 4] = [(0, 1), (-1, 0), (0, -1), (1, 0)];
                let (a, b) = match slot {
                    0 => (0, 0),
                    1 => (1, 0),
                    2 => (0, 1),
                    _ => (1, 1),
                };
                let (ck, cl) = CORNER[corner];
                let k = ck + a * NEXT[corner].0 + b * PREV[corner].0;
                let l = cl + a * NEXT[corner].1 + b * PREV[corner].1;
                (4 * k + l) as usize
            }
            Form::CPatch => 6 * corner + slot,
            Form::Acc if slot < 4 => Form::Bicubic.storage_index(corner, slot),
            Form::Acc => 16 + 6 * corner + (slot - 4),
            Form::Gregory | Form::TriCubic => 5 * corner + slot,
            Form::Gregory4 => 7 * corner + slot,
        }
    }

    /// Points of each boundary curve: 4 (cubic) or 5 (quartic,
    /// [`Form::Gregory4`]). Every class of a scheme must agree, because an
    /// edge between two classes is one curve evaluated from both sides.
    pub fn curve_points(self) -> usize {
        match self {
            Form::Gregory4 => 5,
            _ => 4,
        }
    }

    /// Stored indices of the boundary curve of local edge `edge`
    /// (`v_edge → v_{edge+1}`), in that direction: [`Form::curve_points`]
    /// of them.
    pub fn edge_curve(self, edge: usize) -> Vec<usize> {
        let next = (edge + 1) % self.sides();
        match self {
            // b00 of corner k, b10 of corner k, b01 of corner k+1, b00 of corner k+1.
            Form::Bicubic | Form::Acc => vec![
                self.storage_index(edge, 0),
                self.storage_index(edge, 1),
                self.storage_index(next, 2),
                self.storage_index(next, 0),
            ],
            // (v^i, t^i_0, t^{i+1}_1, v^{i+1}) — pccm.md §4.1.
            Form::CPatch => vec![6 * edge, 6 * edge + 1, 6 * next + 2, 6 * next],
            // (P_k, E_k⁺, E_{k+1}⁻, P_{k+1}) — gregory.md §2; the triangle's
            // (b_k, bn_k, bp_{k+1}, b_{k+1}) has the same layout.
            Form::Gregory | Form::TriCubic => {
                vec![5 * edge, 5 * edge + 1, 5 * next + 2, 5 * next]
            }
            // (P_k, E_k⁺, M_k, E_{k+1}⁻, P_{k+1}): the quartic boundary.
            Form::Gregory4 => vec![7 * edge, 7 * edge + 1, 7 * edge + 3, 7 * next + 2, 7 * next],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bicubic_storage_is_a_permutation_matching_pccm_4_2() {
        let f = Form::Bicubic;
        let mut seen = [false; 16];
        for c in 0..4 {
            for s in 0..4 {
                seen[f.storage_index(c, s)] = true;
            }
        }
        assert!(seen.iter().all(|x| *x));
        // pccm.md §4.2: G[1][0] = e^0_0, G[0][1] = e^0_1, G[3][1] = e^1_0,
        // G[2][0] = e^1_1, G[2][3] = e^2_0, G[3][2] = e^2_1, G[0][2] = e^3_0, G[1][3] = e^3_1.
        assert_eq!(f.storage_index(0, 1), 4);
        assert_eq!(f.storage_index(0, 2), 1);
        assert_eq!(f.storage_index(1, 1), 13);
        assert_eq!(f.storage_index(1, 2), 8);
        assert_eq!(f.storage_index(2, 1), 11);
        assert_eq!(f.storage_index(2, 2), 14);
        assert_eq!(f.storage_index(3, 1), 2);
        assert_eq!(f.storage_index(3, 2), 7);
        assert_eq!(f.storage_index(2, 3), 10);
    }

    #[test]
    fn edge_curves_run_corner_to_corner() {
        for f in [
            Form::Bicubic,
            Form::CPatch,
            Form::Acc,
            Form::Gregory,
            Form::Gregory4,
            Form::TriCubic,
        ] {
            for e in 0..f.sides() {
                let c = f.edge_curve(e);
                assert_eq!(c.len(), f.curve_points());
                assert_eq!(c[0], f.storage_index(e, 0));
                assert_eq!(c[c.len() - 1], f.storage_index((e + 1) % f.sides(), 0));
            }
        }
        // Gregory4: 29 points, the centre last; edge 1 is (P1, E1+, M1, E2-, P2).
        assert_eq!(Form::Gregory4.num_points(), 29);
        assert_eq!(Form::Gregory4.single_index(0), 28);
        assert_eq!(Form::Gregory4.edge_curve(1), vec![7, 8, 10, 16, 14]);
        // Bicubic edge 0 is the row v = 0: G[0][0], G[1][0], G[2][0], G[3][0].
        assert_eq!(Form::Bicubic.edge_curve(0), [0, 4, 8, 12]);
        // Edge 2 runs v2 -> v3 along v = 1, u decreasing.
        assert_eq!(Form::Bicubic.edge_curve(2), [15, 11, 7, 3]);
    }

    #[test]
    fn acc_tangent_slots_cover_u_and_v_once() {
        let mut seen_u = [[0; 4]; 3];
        let mut seen_v = [[0; 3]; 4];
        for c in 0..4 {
            for s in 4..10 {
                let t = Form::acc_tangent_slot(c, s);
                if t.in_v {
                    seen_v[t.a][t.b] += 1;
                } else {
                    seen_u[t.a][t.b] += 1;
                }
            }
        }
        assert!(seen_u.iter().flatten().all(|&k| k == 1), "{seen_u:?}");
        assert!(seen_v.iter().flatten().all(|&k| k == 1), "{seen_v:?}");
        // acc.md §4(b): corner tangents U[0][0] = T0 (c0), V[3][0] = T0 (c1),
        // U[2][3] = −T0 (c2), V[0][2] = −T0 (c3); U[2][0] = −T1 (c1).
        let t = |c, s| Form::acc_tangent_slot(c, s);
        assert_eq!(
            t(0, 4),
            TangentSlot {
                in_v: false,
                a: 0,
                b: 0,
                negate: false
            }
        );
        assert_eq!(
            t(1, 4),
            TangentSlot {
                in_v: true,
                a: 3,
                b: 0,
                negate: false
            }
        );
        assert_eq!(
            t(2, 4),
            TangentSlot {
                in_v: false,
                a: 2,
                b: 3,
                negate: true
            }
        );
        assert_eq!(
            t(3, 4),
            TangentSlot {
                in_v: true,
                a: 0,
                b: 2,
                negate: true
            }
        );
        assert_eq!(
            t(1, 8),
            TangentSlot {
                in_v: false,
                a: 2,
                b: 0,
                negate: true
            }
        );
        assert_eq!(
            t(3, 8),
            TangentSlot {
                in_v: false,
                a: 0,
                b: 3,
                negate: false
            }
        );
        // Cross-boundary coefficients: V[1][0] (c0 db10), U[0][1] (c0 da01).
        assert_eq!(
            t(0, 9),
            TangentSlot {
                in_v: true,
                a: 1,
                b: 0,
                negate: false
            }
        );
        assert_eq!(
            t(0, 5),
            TangentSlot {
                in_v: false,
                a: 0,
                b: 1,
                negate: false
            }
        );
    }
}

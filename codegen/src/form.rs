//! Patch forms: the small fixed set of surface representations a scheme's
//! patch stage can produce, and what their control points mean.
//!
//! A form names its per-corner control-point slots (what a scheme's `out`
//! statements must fill), how they are stored, and which four stored points
//! make up the cubic boundary curve of each edge (the curve the shared edge
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
}

impl Form {
    pub fn from_name(name: &str) -> Option<Form> {
        match name {
            "bicubic" => Some(Form::Bicubic),
            "cpatch" => Some(Form::CPatch),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Form::Bicubic => "bicubic",
            Form::CPatch => "cpatch",
        }
    }

    /// Per-corner slots a scheme must define with `out SLOT[i] = …`.
    pub fn slots(self) -> &'static [&'static str] {
        match self {
            // Corner-local Bézier indices: b10 is one step toward v_{i+1},
            // b01 one step toward v_{i-1}, b11 the interior point.
            Form::Bicubic => &["b00", "b10", "b01", "b11"],
            Form::CPatch => &["v", "t0", "t1", "b211", "b121", "b112"],
        }
    }

    /// Number of stored control points.
    pub fn num_points(self) -> usize {
        4 * self.slots().len()
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
        }
    }

    /// Stored indices of the cubic boundary curve of local edge `edge`
    /// (`v_edge → v_{edge+1}`), in that direction.
    pub fn edge_curve(self, edge: usize) -> [usize; 4] {
        let next = (edge + 1) % 4;
        match self {
            // b00 of corner k, b10 of corner k, b01 of corner k+1, b00 of corner k+1.
            Form::Bicubic => [
                self.storage_index(edge, 0),
                self.storage_index(edge, 1),
                self.storage_index(next, 2),
                self.storage_index(next, 0),
            ],
            // (v^i, t^i_0, t^{i+1}_1, v^{i+1}) — pccm.md §4.1.
            Form::CPatch => [6 * edge, 6 * edge + 1, 6 * next + 2, 6 * next],
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
        for f in [Form::Bicubic, Form::CPatch] {
            for e in 0..4 {
                let c = f.edge_curve(e);
                assert_eq!(c[0], f.storage_index(e, 0));
                assert_eq!(c[3], f.storage_index((e + 1) % 4, 0));
            }
        }
        // Bicubic edge 0 is the row v = 0: G[0][0], G[1][0], G[2][0], G[3][0].
        assert_eq!(Form::Bicubic.edge_curve(0), [0, 4, 8, 12]);
        // Edge 2 runs v2 -> v3 along v = 1, u decreasing.
        assert_eq!(Form::Bicubic.edge_curve(2), [15, 11, 7, 3]);
    }
}

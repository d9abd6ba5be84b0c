//! The per-valence stencil table: every vertex-stage output of every scheme
//! as a row of f32 weights over the `2n + 1` ring slots, for valences
//! 3..=MAX_VALENCE, plus one row of per-valence constants per valence.
//!
//! Plain flat data (OpenSubdiv `Far` style): a `rows × width` f32 matrix and
//! a manifest that says what each row is. On the GPU it is an `R32Float`
//! texture (row = y, slot = x); on the CPU a slice.

use crate::front::scheme::Scheme;
use serde::Serialize;

/// Default largest valence.
pub const DEFAULT_MAX_VALENCE: u32 = 32;

/// Rows one scheme occupies.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct SchemeRows {
    pub scheme: String,
    /// `valence_row_base[n]` = first row of valence n's block (0 for n < 3).
    pub valence_row_base: Vec<u32>,
    /// Row of valence 3's constants; valence n is `const_row_base + n - 3`.
    pub const_row_base: u32,
    /// Names of the per-valence constants, in column order.
    pub consts: Vec<String>,
    /// Vertex-stage outputs in row order within a valence block.
    pub outputs: Vec<OutputInfo>,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct OutputInfo {
    pub name: String,
    /// A family over sectors (`n` rows per valence) or a single row.
    pub per_sector: bool,
    /// `point` (weights sum to 1) or `vector` (sum to 0).
    pub kind: &'static str,
}

/// What one row holds.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RowInfo {
    pub row: u32,
    pub scheme: String,
    /// Output name, or `constants`.
    pub output: String,
    /// Sector index for per-sector outputs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sector: Option<u32>,
    pub valence: u32,
    /// Number of meaningful columns (2n + 1 for stencil rows).
    pub length: u32,
    /// Non-zero mask over the row's columns, as a string of '0'/'1'.
    pub nonzero: String,
}

/// The table and its manifest.
#[derive(Clone, Debug, PartialEq)]
pub struct StencilTable {
    pub max_valence: u32,
    /// Columns: 2·max_valence + 1.
    pub width: u32,
    /// `rows × width` weights, row-major.
    pub weights: Vec<f32>,
    pub rows: Vec<RowInfo>,
    pub schemes: Vec<SchemeRows>,
}

#[derive(Serialize)]
struct Manifest<'a> {
    format: &'static str,
    generator: String,
    max_valence: u32,
    width: u32,
    height: u32,
    texel: &'static str,
    layout: &'static str,
    schemes: &'a [SchemeRows],
    rows: &'a [RowInfo],
}

impl StencilTable {
    /// Build the table for `schemes`, all valences 3..=max_valence, weights
    /// computed in f64 from the symbolic expressions and rounded once to f32.
    pub fn build(schemes: &[Scheme], max_valence: u32) -> StencilTable {
        let width = 2 * max_valence + 1;
        let mut weights = Vec::new();
        let mut rows = Vec::new();
        let mut infos = Vec::new();
        let push_row =
            |weights: &mut Vec<f32>, rows: &mut Vec<RowInfo>, info: RowInfo, w: &[f64]| {
                let mut line = vec![0f32; width as usize];
                for (dst, src) in line.iter_mut().zip(w) {
                    *dst = *src as f32;
                }
                weights.extend_from_slice(&line);
                rows.push(info);
            };
        for s in schemes {
            let mut valence_row_base = vec![0u32; max_valence as usize + 1];
            for n in 3..=max_valence {
                valence_row_base[n as usize] = rows.len() as u32;
                for (def, sector, w) in s.vertex_rows(n) {
                    let d = &s.vertex[def];
                    let info = RowInfo {
                        row: rows.len() as u32,
                        scheme: s.name.clone(),
                        output: d.name.clone(),
                        sector: d.indexed.then_some(sector),
                        valence: n,
                        length: 2 * n + 1,
                        nonzero: w
                            .iter()
                            .map(|x| if *x as f32 != 0.0 { '1' } else { '0' })
                            .collect(),
                    };
                    push_row(&mut weights, &mut rows, info, &w);
                }
            }
            // A scheme without per-valence constants (the triangle schemes,
            // `regular`) reads no constant rows, so it reserves none: the
            // table's height is bounded by the texture limit (8192 rows in
            // WebGPU's defaults), and empty rows only bring it closer.
            let const_row_base = rows.len() as u32;
            for n in (3..=max_valence).filter(|_| !s.consts.is_empty()) {
                let vals = s.const_values(n);
                let info = RowInfo {
                    row: rows.len() as u32,
                    scheme: s.name.clone(),
                    output: "constants".into(),
                    sector: None,
                    valence: n,
                    length: vals.len() as u32,
                    nonzero: vals
                        .iter()
                        .map(|x| if *x as f32 != 0.0 { '1' } else { '0' })
                        .collect(),
                };
                push_row(&mut weights, &mut rows, info, &vals);
            }
            infos.push(SchemeRows {
                scheme: s.name.clone(),
                valence_row_base,
                const_row_base,
                consts: s.consts.iter().map(|c| c.name.clone()).collect(),
                outputs: s
                    .outputs()
                    .map(|(_, d)| OutputInfo {
                        name: d.name.clone(),
                        per_sector: d.indexed,
                        kind: if d.kind == crate::front::dsl::DefKind::Vector {
                            "vector"
                        } else {
                            "point"
                        },
                    })
                    .collect(),
            });
        }
        StencilTable {
            max_valence,
            width,
            weights,
            rows,
            schemes: infos,
        }
    }

    pub fn height(&self) -> u32 {
        self.rows.len() as u32
    }

    pub fn weight(&self, row: u32, col: u32) -> f32 {
        self.weights[(row * self.width + col) as usize]
    }

    /// Little-endian f32 bytes, row-major: the texture's contents.
    pub fn to_le_bytes(&self) -> Vec<u8> {
        self.weights.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    /// The JSON manifest.
    pub fn manifest_json(&self) -> String {
        let m = Manifest {
            format: "tessgen-stencil-table/1",
            generator: format!("tessgen {}", env!("CARGO_PKG_VERSION")),
            max_valence: self.max_valence,
            width: self.width,
            height: self.height(),
            texel: "f32 little-endian (R32Float)",
            layout: "row-major, height rows of width f32; row = (scheme, valence, output, sector) \
                     as listed in `rows`, column = ring slot [p, p_0 .. p_{2n-1}] \
                     (or constant index for `constants` rows); unused columns are 0",
            schemes: &self.schemes,
            rows: &self.rows,
        };
        let mut s = serde_json::to_string_pretty(&m).unwrap_or_default();
        s.push('\n');
        s
    }
}

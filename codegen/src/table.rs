//! The per-valence stencil table: every vertex-stage output of every scheme
//! as a row of f32 weights over the `2n + 1` ring slots, for valences
//! 3..=MAX_VALENCE, plus one row of per-valence constants per valence.
//!
//! Plain flat data (OpenSubdiv `Far` style): a `rows × width` f32 matrix and
//! a manifest that says what each row is. On the GPU it is an `R32Float`
//! texture whose rows wrap into column blocks of [`TABLE_BLOCK_ROWS`]
//! ([`StencilTable::texture`]); on the CPU a slice of the logical rows.
//!
//! Sector rows (crease and corner vertices, docs/boundaries.md §3) live in a
//! second column region of the same texture, from [`StencilTable::sector_column`]
//! on: a sector of `m` faces has `2m + 2` partial-ring slots, and keeping
//! them beside the per-valence rows rather than below keeps the logical
//! height down and the bindings unchanged.

use crate::front::scheme::{max_sector_faces, virtual_valence, Scheme, SectorKind};
use serde::Serialize;

/// Default largest valence.
pub const DEFAULT_MAX_VALENCE: u32 = 32;

/// Rows per column block of the stencil texture. The logical table grows
/// with every scheme (11 k rows with `g1cc`), past the 8,192-texel side of
/// WebGPU's default limits; 4,096 is the side Vulkan guarantees
/// (`maxImageDimension2D`), so wrapping the rows into blocks of 4,096 keeps
/// the texture inside every backend's minimum for up to ⌊4096 / width⌋
/// blocks (167 k rows at width 99).
pub const TABLE_BLOCK_ROWS: u32 = 4096;

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
    /// `sector_row_base[kind · max_sector_faces + m − 1]` = first row of the
    /// sector block (kind, m faces) in the sector column region (all 0 for
    /// schemes without a vertex stage).
    pub sector_row_base: Vec<u32>,
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
    /// Sector rows: `crease` or `corner` (the row's columns start at
    /// `sector_column`; `valence` is then the virtual valence n'(m)).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kind: Option<&'static str>,
    /// Sector rows: faces m of the sector.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub faces: Option<u32>,
}

/// The table and its manifest.
#[derive(Clone, Debug, PartialEq)]
pub struct StencilTable {
    pub max_valence: u32,
    /// Columns: 2·max_valence + 1 ring slots, then the sector region's
    /// 2·max_sector_faces + 2 partial-ring slots.
    pub width: u32,
    /// First column of the sector region (= 2·max_valence + 1).
    pub sector_column: u32,
    /// Largest sector in faces (max_valence / 2).
    pub max_sector_faces: u32,
    /// `height × width` weights, row-major.
    pub weights: Vec<f32>,
    /// Per-valence rows and constants (columns from 0).
    pub rows: Vec<RowInfo>,
    /// Sector rows (columns from `sector_column`); row `r` of this list is
    /// texture row `r`.
    pub sector_rows: Vec<RowInfo>,
    pub schemes: Vec<SchemeRows>,
}

#[derive(Serialize)]
struct Manifest<'a> {
    format: &'static str,
    generator: String,
    max_valence: u32,
    width: u32,
    height: u32,
    block_rows: u32,
    texture_width: u32,
    texture_height: u32,
    sector_column: u32,
    max_sector_faces: u32,
    texel: &'static str,
    layout: &'static str,
    schemes: &'a [SchemeRows],
    rows: &'a [RowInfo],
    sector_rows: &'a [RowInfo],
}

impl StencilTable {
    /// Build the table for `schemes`, all valences 3..=max_valence, weights
    /// computed in f64 from the symbolic expressions and rounded once to f32.
    pub fn build(schemes: &[Scheme], max_valence: u32) -> StencilTable {
        let width = 2 * max_valence + 1;
        let max_m = max_sector_faces(max_valence);
        let sector_width = 2 * max_m + 2;
        let mut weights = Vec::new();
        let mut rows = Vec::new();
        let mut sector_weights: Vec<f32> = Vec::new();
        let mut sector_rows: Vec<RowInfo> = Vec::new();
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
                        kind: None,
                        faces: None,
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
                    kind: None,
                    faces: None,
                };
                push_row(&mut weights, &mut rows, info, &vals);
            }
            // Every scheme declares the full index (triangle schemes: zeros,
            // no rows), so the constant array is never empty.
            let mut sector_row_base = Vec::new();
            let quad = s.vertex.iter().any(|d| d.exported());
            for kind in SectorKind::ALL {
                for m in 1..=max_m {
                    sector_row_base.push(if quad { sector_rows.len() as u32 } else { 0 });
                    if !quad {
                        continue;
                    }
                    for (def, j, w) in s.sector_rows(kind, m) {
                        let d = &s.vertex[def];
                        let info = RowInfo {
                            row: sector_rows.len() as u32,
                            scheme: s.name.clone(),
                            output: d.name.clone(),
                            sector: d.indexed.then_some(j),
                            valence: virtual_valence(m),
                            length: 2 * m + 2,
                            nonzero: w
                                .iter()
                                .map(|x| if *x as f32 != 0.0 { '1' } else { '0' })
                                .collect(),
                            kind: Some(kind.name()),
                            faces: Some(m),
                        };
                        let mut line = vec![0f32; sector_width as usize];
                        for (dst, src) in line.iter_mut().zip(&w) {
                            *dst = *src as f32;
                        }
                        sector_weights.extend_from_slice(&line);
                        sector_rows.push(info);
                    }
                }
            }
            infos.push(SchemeRows {
                scheme: s.name.clone(),
                valence_row_base,
                const_row_base,
                sector_row_base,
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
        // Place the sector region beside the per-valence rows.
        let height = rows.len().max(sector_rows.len());
        let total = (width + sector_width) as usize;
        let mut merged = vec![0f32; height * total];
        for (r, line) in weights.chunks(width as usize).enumerate() {
            merged[r * total..r * total + width as usize].copy_from_slice(line);
        }
        for (r, line) in sector_weights.chunks(sector_width as usize).enumerate() {
            merged[r * total + width as usize..(r + 1) * total].copy_from_slice(line);
        }
        StencilTable {
            max_valence,
            width: total as u32,
            sector_column: width,
            max_sector_faces: max_m,
            weights: merged,
            rows,
            sector_rows,
            schemes: infos,
        }
    }

    pub fn height(&self) -> u32 {
        self.rows.len().max(self.sector_rows.len()) as u32
    }

    /// Weight of sector row `row` at partial-ring slot `slot`.
    pub fn sector_weight(&self, row: u32, slot: u32) -> f32 {
        self.weight(row, self.sector_column + slot)
    }

    pub fn weight(&self, row: u32, col: u32) -> f32 {
        self.weights[(row * self.width + col) as usize]
    }

    /// Column blocks of the texture: rows past [`TABLE_BLOCK_ROWS`] wrap
    /// into a further block of `width` columns to the right.
    pub fn blocks(&self) -> u32 {
        self.height().div_ceil(TABLE_BLOCK_ROWS).max(1)
    }

    /// Width of the texture in texels: `width · blocks`.
    pub fn texture_width(&self) -> u32 {
        self.width * self.blocks()
    }

    /// Height of the texture in texels: the rows of the first block.
    pub fn texture_height(&self) -> u32 {
        self.height().clamp(1, TABLE_BLOCK_ROWS)
    }

    /// The texture's texels, row-major (`texture_height × texture_width`):
    /// logical row `r`, column `c` at texel `(c + width·⌊r / B⌋, r mod B)`,
    /// B = [`TABLE_BLOCK_ROWS`] — the same mapping every shader reads with
    /// ([`crate::plan::flat::table_texel`]). Texels of the last block past
    /// the table's rows are 0.
    pub fn texture(&self) -> Vec<f32> {
        let (tw, w) = (self.texture_width() as usize, self.width as usize);
        let b = TABLE_BLOCK_ROWS as usize;
        let mut t = vec![0f32; tw * self.texture_height() as usize];
        for (r, line) in self.weights.chunks(w).enumerate() {
            let at = (r % b) * tw + (r / b) * w;
            t[at..at + w].copy_from_slice(line);
        }
        t
    }

    /// Little-endian f32 bytes of [`StencilTable::texture`]: the file a
    /// host uploads as it is.
    pub fn to_le_bytes(&self) -> Vec<u8> {
        self.texture()
            .iter()
            .flat_map(|w| w.to_le_bytes())
            .collect()
    }

    /// The JSON manifest.
    pub fn manifest_json(&self) -> String {
        let m = Manifest {
            format: "tessgen-stencil-table/1",
            generator: format!("tessgen {}", env!("CARGO_PKG_VERSION")),
            max_valence: self.max_valence,
            width: self.width,
            height: self.height(),
            block_rows: TABLE_BLOCK_ROWS,
            texture_width: self.texture_width(),
            texture_height: self.texture_height(),
            sector_column: self.sector_column,
            max_sector_faces: self.max_sector_faces,
            texel: "f32 little-endian (R32Float)",
            layout: "logical table: height rows of width f32, wrapped into a texture of \
                     texture_width × texture_height texels (the file, row-major): logical row r, \
                     column c is texel (c + width·floor(r / block_rows), r mod block_rows); \
                     columns 0 .. sector_column: \
                     row = (scheme, valence, output, sector) as listed in `rows`, column = ring \
                     slot [p, p_0 .. p_{2n-1}] (or constant index for `constants` rows); columns \
                     sector_column ..: row = (scheme, kind, faces m, output, ring position) as \
                     listed in `sector_rows`, column sector_column + k = partial-ring slot k of \
                     [p, q_0, d_0, .., q_m]; unused columns are 0",
            schemes: &self.schemes,
            rows: &self.rows,
            sector_rows: &self.sector_rows,
        };
        let mut s = serde_json::to_string_pretty(&m).unwrap_or_default();
        s.push('\n');
        s
    }
}

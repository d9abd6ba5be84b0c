//! The generated CPU kernels (see `build.rs`) and the stencil table they read.

include!(concat!(env!("OUT_DIR"), "/rust/tessgen.rs"));

use std::sync::OnceLock;

/// The stencil texture generated with the kernels: `TABLE_TEXTURE_HEIGHT ×
/// TABLE_TEXTURE_WIDTH` f32, row-major, the logical rows wrapped into column
/// blocks of `TABLE_BLOCK_ROWS` (`generated/README.md`). What the GPU
/// backends upload as it is.
pub fn table_texture() -> &'static [f32] {
    static TEXTURE: OnceLock<Vec<f32>> = OnceLock::new();
    TEXTURE.get_or_init(|| {
        include_bytes!(concat!(env!("OUT_DIR"), "/table/stencils.f32"))
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    })
}

/// The stencil table's logical rows, row-major, `TABLE_WIDTH` columns: what
/// the CPU kernels index (`row·TABLE_WIDTH + column`). Unwrapped once from
/// [`table_texture`].
pub fn table() -> &'static [f32] {
    static TABLE: OnceLock<Vec<f32>> = OnceLock::new();
    TABLE.get_or_init(|| {
        use common::{TABLE_BLOCK_ROWS, TABLE_TEXTURE_WIDTH, TABLE_WIDTH};
        unwrap_table(
            table_texture(),
            TABLE_WIDTH,
            TABLE_TEXTURE_WIDTH,
            TABLE_BLOCK_ROWS,
        )
    })
}

/// The logical rows of a stencil texture laid out as [`table_texture`]
/// (`texture_width` texels a row; block `k` of `block_rows` rows sits at
/// columns `k·table_width..`): rows of `table_width` f32, row-major. Takes
/// the sizes as arguments so a crate with its own generated table (the
/// `custom_scheme` example) unwraps with its constants.
pub fn unwrap_table(
    texture: &[f32],
    table_width: u32,
    texture_width: u32,
    block_rows: u32,
) -> Vec<f32> {
    let (w, tw) = (table_width as usize, texture_width as usize);
    let h = (texture.len() / tw.max(1)).min(block_rows as usize);
    let mut out = Vec::with_capacity(texture.len());
    for block in 0..tw / w.max(1) {
        for y in 0..h {
            let at = y * tw + block * w;
            if let Some(line) = texture.get(at..at + w) {
                out.extend_from_slice(line);
            }
        }
    }
    out
}

/// Scheme names are DSL identifiers (`gregory_osd`); the CLI spelling
/// `gregory-osd` names the same scheme.
fn canonical(name: &str) -> String {
    name.replace('-', "_")
}

/// Look a built-in scheme up by name (`-` and `_` are interchangeable).
pub fn scheme(name: &str) -> Option<&'static common::SchemeKernels> {
    let name = canonical(name);
    SCHEMES.iter().copied().find(|s| s.name == name)
}

/// Names of the schemes compiled into this runtime.
pub fn scheme_names() -> Vec<&'static str> {
    SCHEMES.iter().map(|s| s.name).collect()
}

mod wgsl_index {
    include!(concat!(env!("OUT_DIR"), "/wgsl_index.rs"));
}

/// The generated WGSL module of a scheme.
pub fn wgsl(name: &str) -> Option<&'static str> {
    let name = canonical(name);
    wgsl_index::WGSL
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| *s)
}

/// An emitted GLSL or HLSL file by its path in the generated tree
/// (`glsl/acc.tese`, `hlsl/acc.hlsl`); built only with the `vulkan` feature.
pub fn shader(path: &str) -> Option<&'static str> {
    wgsl_index::SHADERS
        .iter()
        .find(|(p, _)| *p == path)
        .map(|(_, s)| *s)
}

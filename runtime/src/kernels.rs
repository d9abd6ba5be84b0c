//! The generated CPU kernels (see `build.rs`) and the stencil table they read.

include!(concat!(env!("OUT_DIR"), "/rust/tessgen.rs"));

use std::sync::OnceLock;

/// The stencil table generated with the kernels (row-major f32).
pub fn table() -> &'static [f32] {
    static TABLE: OnceLock<Vec<f32>> = OnceLock::new();
    TABLE.get_or_init(|| {
        include_bytes!(concat!(env!("OUT_DIR"), "/table/stencils.f32"))
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    })
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

//! glTF 2.0 binary (`.glb`): one mesh, one triangle primitive with
//! `POSITION` and `NORMAL` (interleaved in one buffer view, stride 24) and
//! `u32` indices, in one node of one scene. The JSON chunk is built and
//! serialised with `gltf-json`; the binary chunk is the vertex and index
//! files appended as they are (both already little-endian and 4-byte
//! aligned). `tests/tests/export.rs` re-reads the file with the `gltf`
//! crate, which validates it, and checks counts, bounds and closure.

use super::{Counts, Part, VERTEX_BYTES};
use gltf_json as json;
use json::validation::{Checked::Valid, USize64};
use std::collections::BTreeMap;
use std::io::Write;

/// The glb container's length field is a `u32`.
const GLB_MAX: u64 = u32::MAX as u64;

fn accessor(
    view: json::Index<json::buffer::View>,
    offset: u64,
    count: u64,
    component: json::accessor::ComponentType,
    type_: json::accessor::Type,
    bounds: Option<(glam::Vec3, glam::Vec3)>,
) -> json::Accessor {
    json::Accessor {
        buffer_view: Some(view),
        byte_offset: Some(USize64(offset)),
        count: USize64(count),
        component_type: Valid(json::accessor::GenericComponentType(component)),
        extensions: None,
        extras: Default::default(),
        type_: Valid(type_),
        min: bounds.map(|(lo, _)| json::Value::from(vec![lo.x, lo.y, lo.z])),
        max: bounds.map(|(_, hi)| json::Value::from(vec![hi.x, hi.y, hi.z])),
        name: None,
        normalized: false,
        sparse: None,
    }
}

fn view(
    offset: u64,
    length: u64,
    stride: Option<usize>,
    target: json::buffer::Target,
) -> json::buffer::View {
    json::buffer::View {
        buffer: json::Index::new(0),
        byte_length: USize64(length),
        byte_offset: Some(USize64(offset)),
        byte_stride: stride.map(json::buffer::Stride),
        name: None,
        target: Some(Valid(target)),
        extensions: None,
        extras: Default::default(),
    }
}

/// The JSON chunk of a mesh of `counts`.
fn document(counts: &Counts) -> json::Root {
    use json::accessor::{ComponentType, Type};
    let vertex_bytes = counts.vertices * VERTEX_BYTES;
    let index_bytes = counts.triangles * 12;
    let mut root = json::Root {
        asset: json::Asset {
            generator: Some(format!("tessgen {}", env!("CARGO_PKG_VERSION"))),
            ..Default::default()
        },
        ..Default::default()
    };
    root.buffers.push(json::Buffer {
        byte_length: USize64(vertex_bytes + index_bytes),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let vertices = root.push(view(
        0,
        vertex_bytes,
        Some(VERTEX_BYTES as usize),
        json::buffer::Target::ArrayBuffer,
    ));
    let indices = root.push(view(
        vertex_bytes,
        index_bytes,
        None,
        json::buffer::Target::ElementArrayBuffer,
    ));
    let bounds = (counts.vertices > 0).then_some((counts.min, counts.max));
    let position = root.push(accessor(
        vertices,
        0,
        counts.vertices,
        ComponentType::F32,
        Type::Vec3,
        bounds,
    ));
    let normal = root.push(accessor(
        vertices,
        12,
        counts.vertices,
        ComponentType::F32,
        Type::Vec3,
        None,
    ));
    let index = root.push(accessor(
        indices,
        0,
        counts.triangles * 3,
        ComponentType::U32,
        Type::Scalar,
        None,
    ));
    let mut attributes = BTreeMap::new();
    attributes.insert(Valid(json::mesh::Semantic::Positions), position);
    attributes.insert(Valid(json::mesh::Semantic::Normals), normal);
    let mesh = root.push(json::Mesh {
        extensions: None,
        extras: Default::default(),
        name: Some("tessgen".into()),
        primitives: vec![json::mesh::Primitive {
            attributes,
            extensions: None,
            extras: Default::default(),
            indices: Some(index),
            material: None,
            mode: Valid(json::mesh::Mode::Triangles),
            targets: None,
        }],
        weights: None,
    });
    let node = root.push(json::Node {
        mesh: Some(mesh),
        ..Default::default()
    });
    let scene = root.push(json::Scene {
        extensions: None,
        extras: Default::default(),
        name: None,
        nodes: vec![node],
    });
    root.scene = Some(scene);
    root
}

pub(crate) fn write(
    out: &mut impl Write,
    counts: &Counts,
    vertices: &mut Part,
    indices: &mut Part,
) -> std::io::Result<()> {
    // glTF accessors hold at least one element.
    if counts.vertices == 0 || counts.triangles == 0 {
        return Err(std::io::Error::other(
            "the result has no triangles (every face a hole?): a .glb cannot hold an empty mesh",
        ));
    }
    let mut text = json::serialize::to_vec(&document(counts)).map_err(std::io::Error::other)?;
    // Chunks are 4-byte aligned: JSON padded with spaces.
    while text.len() % 4 != 0 {
        text.push(b' ');
    }
    let bin = counts.vertices * VERTEX_BYTES + counts.triangles * 12;
    let total = 12 + 8 + text.len() as u64 + 8 + bin;
    if total > GLB_MAX {
        return Err(std::io::Error::other(format!(
            "a .glb holds at most 4 GiB; this mesh needs {total} bytes ({} vertices, {} triangles): write .ply or .obj",
            counts.vertices, counts.triangles
        )));
    }
    out.write_all(b"glTF")?;
    out.write_all(&2u32.to_le_bytes())?;
    out.write_all(&(total as u32).to_le_bytes())?;
    out.write_all(&(text.len() as u32).to_le_bytes())?;
    out.write_all(b"JSON")?;
    out.write_all(&text)?;
    out.write_all(&(bin as u32).to_le_bytes())?;
    out.write_all(b"BIN\0")?;
    vertices.append_to(out)?;
    indices.append_to(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mesh past the container's 4 GiB is an error naming the formats
    /// that hold it, before a byte is written.
    #[test]
    fn a_glb_over_4_gib_is_refused() {
        let dir = std::env::temp_dir().join(format!("tessgen-glb-{}", std::process::id()));
        let part = |ext: &str| {
            let mut p = dir.as_os_str().to_owned();
            p.push(ext);
            Part::create(p.into()).expect("part")
        };
        let (mut v, mut i) = (part(".v"), part(".i"));
        let counts = Counts {
            vertices: 100_000_000,
            triangles: 200_000_000,
            min: glam::Vec3::ZERO,
            max: glam::Vec3::ONE,
        };
        let mut out = Vec::new();
        let e = write(&mut out, &counts, &mut v, &mut i).expect_err("too big");
        assert!(e.to_string().contains("at most 4 GiB"), "{e}");
        assert!(e.to_string().contains("write .ply or .obj"), "{e}");
        assert!(out.is_empty());
    }
}

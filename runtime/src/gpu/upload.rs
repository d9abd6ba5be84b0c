//! What every GPU backend uploads for a mesh, backend-neutral: one byte
//! buffer per binding of the ABI (`tessgen-codegen`'s `backend::abi`), the
//! patches sorted by facet class, and each class's range. The wgpu path
//! ([`crate::gpu`]) and the Vulkan tessellation harness ([`crate::gpu::vulkan`])
//! both build their buffers from an [`Upload`], so they run the emitted
//! shaders on the same data.

use crate::cpu::{self, TessError};
use crate::kernels::common::SchemeKernels;
use crate::mesh::topology::Topology;
use glam::{Mat4, Vec3};

/// Binding numbers, from the ABI (`tessgen-codegen`'s `backend::abi`,
/// printed into [`crate::abi`] by build.rs); re-exported here for the
/// callers that name `upload::binding`.
pub use crate::abi::binding;
/// Size of the Params uniform block in bytes (from the ABI).
pub use crate::abi::PARAMS_SIZE;

/// Errors building an [`Upload`].
#[derive(Debug, thiserror::Error)]
pub enum UploadError {
    #[error(transparent)]
    Tess(#[from] TessError),
    #[error("positions: expected {expected}, got {got}")]
    PositionCount { expected: usize, got: usize },
    #[error(
        "refinement: the stencil table has {rows} rows for {vertices} refined vertices, or a \
         term names base vertex {index} of {base}"
    )]
    Refinement {
        rows: usize,
        vertices: usize,
        index: u32,
        base: usize,
    },
}

/// The refinement stage of an [`Upload`] (docs/boundaries.md §8): the GPU
/// computes the refined positions from the base positions and the stencil
/// table before the vertex stage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RefineLayout {
    /// Refined vertices (stencil rows), = the vertex stage's positions.
    pub rows: u32,
    /// Base-mesh positions (`refine_base`), what an animation updates.
    pub base: u32,
}

/// One class's patches: a contiguous range of `patch_faces` and of the
/// control-point buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ClassRange {
    pub class: u32,
    /// First patch (index into `patch_faces`).
    pub first: u32,
    pub count: u32,
    /// The first `emitting` patches of the range have a limit surface and
    /// are drawn; the rest (holes) are built but not drawn.
    pub emitting: u32,
    /// First control point (in points).
    pub cp_base: u32,
    /// Control points per patch.
    pub points: u32,
}

/// One storage buffer's initial contents.
#[derive(Clone, Debug)]
pub struct UploadBuffer {
    pub binding: u32,
    pub label: &'static str,
    pub bytes: Vec<u8>,
    /// Read back by some caller (control points): needs copy-source usage.
    pub read_back: bool,
}

/// The facet data of a quad mesh (topology, rings) or a triangle mesh
/// (corner vertices, normals), ready for upload.
#[derive(Clone, Debug)]
pub struct Upload {
    pub scheme: &'static SchemeKernels,
    /// Face of each patch (patches sorted by class).
    pub patch_faces: Vec<u32>,
    pub classes: Vec<ClassRange>,
    /// Vertices the vertex stage runs over (0 for triangle schemes).
    pub num_vertices: u32,
    /// Control-mesh positions uploaded.
    pub num_positions: u32,
    /// Storage buffers by binding (the table and Params are not here).
    pub buffers: Vec<UploadBuffer>,
    /// The displacement map (binding 24, an `R32Float` texture); a 1×1 zero
    /// map while displacement is off.
    pub displace_map: crate::cpu::displace::DisplaceMap,
    /// The refinement stage, when the positions are refined on the GPU
    /// ([`Upload::with_refinement`]).
    pub refine: Option<RefineLayout>,
}

/// The Params block (`abi::PARAMS`), each field at its generated offset
/// ([`crate::abi::params`]); `flags` and the padding stay 0.
#[allow(clippy::too_many_arguments)]
pub fn params_bytes(
    view_proj: Mat4,
    first: u32,
    count: u32,
    class: u32,
    cp_base: u32,
    level: u32,
    out_base: u32,
) -> Vec<u8> {
    use crate::abi::params;
    let mut b = vec![0u8; PARAMS_SIZE as usize];
    for (i, x) in view_proj.to_cols_array().into_iter().enumerate() {
        let at = params::VIEW_PROJ + 4 * i;
        b[at..at + 4].copy_from_slice(&x.to_le_bytes());
    }
    for (at, x) in [
        (params::FIRST, first),
        (params::COUNT, count),
        (params::CLASS, class),
        (params::CP_BASE, cp_base),
        (params::LEVEL, level),
        (params::OUT_BASE, out_base),
    ] {
        b[at..at + 4].copy_from_slice(&x.to_le_bytes());
    }
    b
}

/// Write `Params.flags` (the `abi::FLAG_*` bits) into a block made by
/// [`params_bytes`].
pub fn set_params_flags(bytes: &mut [u8], flags: u32) {
    let at = crate::abi::params::FLAGS;
    bytes[at..at + 4].copy_from_slice(&flags.to_le_bytes());
}

pub fn u32_bytes(x: &[u32]) -> Vec<u8> {
    // A zero-length storage binding is invalid; pad empty arrays to one element.
    let mut b: Vec<u8> = x.iter().flat_map(|v| v.to_le_bytes()).collect();
    if b.is_empty() {
        b.extend_from_slice(&[0; 4]);
    }
    b
}

pub fn f32_bytes(x: &[f32]) -> Vec<u8> {
    let mut b: Vec<u8> = x.iter().flat_map(|v| v.to_le_bytes()).collect();
    if b.is_empty() {
        b.extend_from_slice(&[0; 4]);
    }
    b
}

pub fn vec3_bytes(x: &[Vec3]) -> Vec<u8> {
    let mut b: Vec<u8> = x
        .iter()
        .flat_map(|v| v.to_array())
        .flat_map(|f| f.to_le_bytes())
        .collect();
    if b.is_empty() {
        b.extend_from_slice(&[0; 12]);
    }
    b
}

/// Patches sorted by class, and within a class the faces that emit
/// first (`no_limit[f]`: holes, faces without a limit surface, which are
/// still built because their points shape the neighbours); control points
/// laid out class by class. A draw of a class's first
/// [`ClassRange::emitting`] patches leaves the holes out.
pub fn class_layout(
    scheme: &SchemeKernels,
    face_class: &[u32],
    no_limit: &[bool],
) -> (Vec<u32>, Vec<ClassRange>, u32) {
    let mut patch_faces = Vec::with_capacity(face_class.len());
    let mut classes = Vec::new();
    let mut cp_base = 0u32;
    let hole = |f: usize| no_limit.get(f).copied().unwrap_or(false);
    for (c, ck) in scheme.classes.iter().enumerate() {
        let first = patch_faces.len() as u32;
        let of_class = |holes: bool| {
            face_class
                .iter()
                .enumerate()
                .filter(move |&(f, k)| *k == c as u32 && hole(f) == holes)
                .map(|(f, _)| f as u32)
        };
        patch_faces.extend(of_class(false));
        let emitting = patch_faces.len() as u32 - first;
        patch_faces.extend(of_class(true));
        let count = patch_faces.len() as u32 - first;
        classes.push(ClassRange {
            class: c as u32,
            first,
            count,
            emitting,
            cp_base,
            points: ck.control_points,
        });
        cp_base += count * ck.control_points;
    }
    (patch_faces, classes, cp_base)
}

fn buf(binding: u32, label: &'static str, bytes: Vec<u8>) -> UploadBuffer {
    UploadBuffer {
        binding,
        label,
        bytes,
        read_back: false,
    }
}

impl Upload {
    /// A quad mesh for a quad scheme: positions, topology, rings, corner
    /// records, zeroed vertex-stage outputs and control points.
    pub fn quad(
        topo: &Topology,
        positions: &[Vec3],
        scheme_name: &str,
    ) -> Result<Upload, UploadError> {
        let scheme = cpu::scheme(scheme_name)?;
        if scheme.sides != 4 {
            return Err(cpu::facet_error(scheme).into());
        }
        let face_class = cpu::face_classes(topo, scheme)?;
        if positions.len() != topo.valence.len() {
            return Err(UploadError::PositionCount {
                expected: topo.valence.len(),
                got: positions.len(),
            });
        }
        let (patch_faces, classes, cp_total) = class_layout(scheme, &face_class, &topo.no_limit);
        let (vertex_out_offsets, total) = cpu::vertex_out_offsets(topo, scheme);
        let (corner_vertex, corner_sector) = cpu::corner_arrays(topo);
        Ok(Upload {
            scheme,
            num_vertices: topo.valence.len() as u32,
            num_positions: positions.len() as u32,
            buffers: vec![
                buf(binding::POSITIONS, "positions", vec3_bytes(positions)),
                buf(binding::VALENCE, "valence", u32_bytes(&topo.valence)),
                buf(
                    binding::RING_OFFSETS,
                    "ring_offsets",
                    u32_bytes(&topo.ring_offsets),
                ),
                buf(binding::RING, "ring", u32_bytes(&topo.ring)),
                buf(
                    binding::VERTEX_OUT_OFFSETS,
                    "vertex_out_offsets",
                    u32_bytes(&vertex_out_offsets),
                ),
                buf(
                    binding::VERTEX_OUT,
                    "vertex_out",
                    vec3_bytes(&vec![Vec3::ZERO; total as usize]),
                ),
                buf(
                    binding::CORNER_VERTEX,
                    "corner_vertex",
                    u32_bytes(&corner_vertex),
                ),
                buf(
                    binding::CORNER_SECTOR,
                    "corner_sector",
                    u32_bytes(&corner_sector),
                ),
                buf(
                    binding::VERTEX_SECTORS,
                    "vertex_sectors",
                    u32_bytes(&topo.vertex_sectors),
                ),
                buf(binding::SECTORS, "sectors", u32_bytes(&topo.sectors)),
                buf(
                    binding::CORNER_VALENCE,
                    "corner_valence",
                    u32_bytes(&topo.corner_valence),
                ),
                UploadBuffer {
                    read_back: true,
                    ..buf(
                        binding::CONTROL_POINTS,
                        "control_points",
                        vec3_bytes(&vec![Vec3::ZERO; cp_total as usize]),
                    )
                },
                buf(binding::PATCH_FACES, "patch_faces", u32_bytes(&patch_faces)),
            ],
            patch_faces,
            classes,
            displace_map: crate::cpu::displace::DisplaceMap::flat(),
            refine: None,
        }
        .with_displacement(&crate::cpu::displace::DisplaceData::off()))
    }

    /// Class and first control point of every face in this upload's layout
    /// (patches sorted by class): what [`crate::cpu::displace::build`] records
    /// for the owners.
    pub fn face_layout(&self) -> (Vec<u32>, Vec<u32>) {
        let mut class = vec![0u32; self.patch_faces.len()];
        let mut cp_base = vec![0u32; self.patch_faces.len()];
        for c in &self.classes {
            for k in 0..c.count {
                let f = self.patch_faces[(c.first + k) as usize] as usize;
                class[f] = c.class;
                cp_base[f] = c.cp_base + k * c.points;
            }
        }
        (class, cp_base)
    }

    /// Displacement of a quad mesh ([`crate::cpu::displace::build`]: texture
    /// coordinates from `mesh`, owners in this upload's class-sorted layout).
    pub fn displaced_quads(
        self,
        mesh: &crate::Mesh,
        topo: &Topology,
        d: &crate::cpu::displace::Displacement,
    ) -> Result<Self, TessError> {
        let (class, cp_base) = self.face_layout();
        let data = crate::cpu::displace::build(mesh, topo, &class, &cp_base, d)?;
        Ok(self.with_displacement(&data))
    }

    /// Displacement of a triangle mesh ([`crate::cpu::displace::build_tri`],
    /// `mesh` the mesh `tri` was made from), owners in this upload's layout.
    pub fn displaced_tris(
        self,
        mesh: &crate::Mesh,
        tri: &crate::mesh::trimesh::TriMesh,
        d: &crate::cpu::displace::Displacement,
    ) -> Result<Self, TessError> {
        let (class, cp_base) = self.face_layout();
        let data = crate::cpu::displace::build_tri(mesh, tri, &class, &cp_base, d)?;
        Ok(self.with_displacement(&data))
    }

    /// Replace the displacement data (bindings 21–24). Built for this
    /// upload's [`Upload::face_layout`].
    pub fn with_displacement(mut self, d: &crate::cpu::displace::DisplaceData) -> Self {
        self.buffers.retain(|b| {
            ![binding::TEXCOORDS, binding::OWNERS, binding::DISPLACE_INFO].contains(&b.binding)
        });
        self.buffers.extend([
            buf(binding::TEXCOORDS, "texcoords", f32_bytes(&d.texcoords)),
            buf(binding::OWNERS, "owners", u32_bytes(&d.owners)),
            buf(binding::DISPLACE_INFO, "displace_info", f32_bytes(&d.info)),
        ]);
        self.displace_map = d.map.clone();
        self
    }

    /// Refine on the GPU: `base` (the base mesh's positions) and `stencils`
    /// (one row per vertex of this upload's refined topology) go into
    /// bindings 34–37, and `positions` (binding 0, which `refine_main`
    /// writes through `refined_positions`, binding 38) starts zeroed, so
    /// every refined position the later stages read comes from the GPU's
    /// refinement stage.
    pub fn with_refinement(
        mut self,
        base: &[Vec3],
        stencils: &crate::mesh::refine::StencilTable,
    ) -> Result<Self, UploadError> {
        let rows = stencils.rows();
        let bad = stencils
            .indices
            .iter()
            .copied()
            .find(|&i| i as usize >= base.len());
        if rows != self.num_positions as usize || bad.is_some() {
            return Err(UploadError::Refinement {
                rows,
                vertices: self.num_positions as usize,
                index: bad.unwrap_or(0),
                base: base.len(),
            });
        }
        for b in &mut self.buffers {
            if b.binding == binding::POSITIONS {
                b.bytes = vec3_bytes(&vec![Vec3::ZERO; rows]);
            }
        }
        self.buffers.extend([
            buf(binding::REFINE_BASE, "refine_base", vec3_bytes(base)),
            buf(
                binding::REFINE_OFFSETS,
                "refine_offsets",
                u32_bytes(&stencils.offsets),
            ),
            buf(
                binding::REFINE_INDICES,
                "refine_indices",
                u32_bytes(&stencils.indices),
            ),
            buf(
                binding::REFINE_WEIGHTS,
                "refine_weights",
                f32_bytes(&stencils.weights),
            ),
        ]);
        self.refine = Some(RefineLayout {
            rows: rows as u32,
            base: base.len() as u32,
        });
        Ok(self)
    }

    /// A triangle mesh for a triangle scheme: corner vertices, positions,
    /// unit normals and crease tags; no vertex stage runs.
    pub fn tri(
        mesh: &crate::mesh::trimesh::TriMesh,
        scheme_name: &str,
    ) -> Result<Upload, UploadError> {
        let scheme = cpu::scheme(scheme_name)?;
        if scheme.sides != 3 {
            return Err(cpu::facet_error(scheme).into());
        }
        let face_class = vec![0u32; mesh.triangles.len()];
        let (patch_faces, classes, cp_total) = class_layout(scheme, &face_class, &[]);
        let corner_vertex: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
        Ok(Upload {
            scheme,
            // Triangle schemes have no vertex stage.
            num_vertices: 0,
            num_positions: mesh.positions.len() as u32,
            buffers: vec![
                buf(binding::POSITIONS, "positions", vec3_bytes(&mesh.positions)),
                buf(binding::NORMALS, "normals", vec3_bytes(&mesh.normals)),
                // Scalar-tagged PN's tags (neutral unless the mesh has a tag
                // file); the other triangle schemes never bind them.
                buf(binding::TAGS, "tags", f32_bytes(&mesh.crease_tags.tags)),
                buf(
                    binding::CREASE,
                    "crease",
                    vec3_bytes(&mesh.crease_tags.crease),
                ),
                buf(
                    binding::CORNER_SIDE,
                    "corner_side",
                    f32_bytes(&mesh.crease_tags.corner_side),
                ),
                buf(
                    binding::CORNER_VERTEX,
                    "corner_vertex",
                    u32_bytes(&corner_vertex),
                ),
                UploadBuffer {
                    read_back: true,
                    ..buf(
                        binding::CONTROL_POINTS,
                        "control_points",
                        vec3_bytes(&vec![Vec3::ZERO; cp_total as usize]),
                    )
                },
                buf(binding::PATCH_FACES, "patch_faces", u32_bytes(&patch_faces)),
            ],
            patch_faces,
            classes,
            displace_map: crate::cpu::displace::DisplaceMap::flat(),
            refine: None,
        }
        .with_displacement(&crate::cpu::displace::DisplaceData::off()))
    }

    /// Samples per patch at `level` (the scheme's `grid_len`).
    pub fn grid_len(&self, level: u32) -> u64 {
        (self.scheme.grid_len)(level) as u64
    }
}

//! The one front door: `tessellate(&mesh, &request)` on any backend.
//!
//! A [`Request`] names the scheme, the sampling (a uniform level, or an
//! adaptive metric with its partitioning), the [`Backend`], and the
//! options (displacement, crease tags, split quads). [`Request::validate`]
//! checks it against the mesh once — scheme, level, tags, partitioning,
//! quads vs triangles, texture coordinates — so the backends only upload
//! and evaluate, and every backend refuses the same requests with the same
//! [`Error`].
//!
//! ```no_run
//! use tessgen_runtime::tessellate::{tessellate, Request};
//! use tessgen_runtime::{weld, Mesh};
//! let mesh = Mesh::from_obj_path("cube.obj")?;
//! let out = tessellate(&mesh, &Request::uniform("pccm", 8))?;
//! assert!(out.weld().is_closed_manifold());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Opening a GPU device is slow (hundreds of ms on lavapipe): a caller
//! that tessellates more than once keeps a [`Session`], which opens each
//! device on first use and reuses it.

mod backend;
pub mod refined;
mod request;
mod stream;
pub use stream::{ChunkError, CHUNK_SAMPLES};

pub use request::{
    power_of_two_level, AdaptiveRequest, Backend, EdgeMetric, Error, Request, Sampling, Validated,
};

use crate::check::obj::ObjStream;
use crate::check::weld::WeldReport;
use crate::cpu::adaptive::AdaptiveTessellation;
use crate::cpu::Tessellation;
use crate::gpu::capture::TriangleCapture;
use crate::mesh::Mesh;
use glam::Vec3;

/// What a backend produced.
#[derive(Clone, Debug, PartialEq)]
pub enum Output {
    /// One grid per face in face order (uniform levels; on the Vulkan
    /// harness, quad schemes only).
    Grid(Tessellation),
    /// The triangles a hardware tessellator emitted (Vulkan: triangle
    /// schemes at a uniform level, every adaptive draw).
    Captured(TriangleCapture),
    /// Adaptive grids of the instanced path (CPU, wgpu): power-of-two
    /// buckets with snapped transitions.
    Instanced(AdaptiveTessellation),
    /// A mesh with triangles or n-gons at a uniform level: base quads as
    /// grids at `N`, the other faces as their sub-faces at `N/2`
    /// ([`refined::PolygonGrids`], docs/boundaries.md §8).
    Polygons(refined::PolygonGrids),
}

impl Output {
    /// The per-face grids, if this is a grid.
    pub fn grid(&self) -> Option<&Tessellation> {
        match self {
            Output::Grid(t) => Some(t),
            _ => None,
        }
    }

    /// The per-face grids, if this is a grid.
    pub fn into_grid(self) -> Option<Tessellation> {
        match self {
            Output::Grid(t) => Some(t),
            _ => None,
        }
    }

    /// Every triangle as world positions (a triangle soup).
    pub fn triangles(&self) -> Vec<[Vec3; 3]> {
        match self {
            Output::Grid(t) => grid_triangles(t),
            Output::Captured(c) => c.triangles(),
            Output::Instanced(a) => a.triangles(),
            Output::Polygons(p) => p.triangles(),
        }
    }

    /// OBJ text: grids and captures in their own group layout
    /// ([`crate::check::obj::to_obj`], [`TriangleCapture::to_obj`]), the instanced
    /// adaptive grids as a triangle soup ([`Output::write_soup`]).
    pub fn to_obj(&self) -> String {
        match self {
            Output::Grid(t) => crate::check::obj::to_obj(t),
            Output::Captured(c) => c.to_obj(),
            Output::Instanced(_) => {
                crate::check::obj::obj_text(|stream| self.write_soup(stream).map(|_| ()))
            }
            Output::Polygons(p) => p.to_obj(),
        }
    }

    /// Append this result to an OBJ stream: grids through
    /// [`ObjStream::write`], instanced adaptive grids as a triangle soup
    /// ([`Output::write_soup`]), polygon grids and captures in their own
    /// layouts ([`refined::PolygonGrids::write_obj`],
    /// [`TriangleCapture::write_obj`]), the header with the stream's first
    /// chunk. Chunks of [`Session::run_chunked`] written one after the other
    /// give the whole result's [`Output::to_obj`], byte for byte.
    pub fn write_obj<W: std::io::Write>(&self, stream: &mut ObjStream<W>) -> std::io::Result<()> {
        match self {
            Output::Grid(t) => stream.write(t),
            Output::Instanced(_) => self.write_soup(stream).map(|_| ()),
            Output::Polygons(p) => p.write_obj(stream),
            Output::Captured(c) => c.write_obj(stream),
        }
    }

    /// Append every triangle as a triangle soup, patch by patch
    /// ([`ObjStream::write_soup_patch`]: `g patch_<face>`, `v` per triangle
    /// corner, `f` per triangle), what `tessellate --adaptive` writes:
    /// instanced grids and grids named after their base face, captured
    /// patches after their index, polygon sub-faces as
    /// `patch_<face>_<corner>`. Returns the triangles written.
    pub fn write_soup<W: std::io::Write>(
        &self,
        stream: &mut ObjStream<W>,
    ) -> std::io::Result<usize> {
        let mut tris = Vec::new();
        let mut written = 0;
        let mut put = |name: String, tris: &mut Vec<[Vec3; 3]>| {
            written += tris.len();
            let r = stream.write_soup_patch(&name, tris);
            tris.clear();
            r
        };
        let mut grid = |t: &Tessellation, name: &dyn Fn(usize) -> String| {
            let (per, local) = (t.grid_len(), t.local_triangles());
            for g in 0..t.faces {
                tris.extend(
                    local
                        .iter()
                        .map(|tri| tri.map(|k| t.positions[g * per + k as usize])),
                );
                put(name(g), &mut tris)?;
            }
            Ok::<(), std::io::Error>(())
        };
        match self {
            Output::Grid(t) => grid(t, &|g| format!("patch_{}", t.face_of(g)))?,
            Output::Polygons(p) => {
                grid(&p.quads, &|g| format!("patch_{}", p.quads.face_of(g)))?;
                grid(&p.subfaces, &|g| {
                    let corner = p.corners.get(g).copied().unwrap_or(0);
                    format!("patch_{}_{corner}", p.subfaces.face_of(g))
                })?;
            }
            Output::Instanced(a) => {
                let mut local = Default::default();
                for g in 0..a.levels.len() {
                    a.grid_triangles(g, &mut local, &mut tris);
                    put(format!("patch_{}", a.face_of(g)), &mut tris)?;
                }
            }
            Output::Captured(c) => {
                for (k, patch) in c.patches.iter().enumerate() {
                    tris.extend(
                        patch
                            .triangles
                            .iter()
                            .map(|t| t.map(|i| patch.positions[i as usize])),
                    );
                    put(format!("patch_{}", c.first_face + k), &mut tris)?;
                }
            }
        }
        Ok(written)
    }

    /// Append every patch to a welded binary mesh ([`crate::export::MeshStream`]:
    /// `.glb`, `.ply`), in the OBJ's patch order: each grid (base grids,
    /// polygon sub-faces, adaptive grids at their own levels) with its local
    /// triangles, each captured
    /// patch with its own. Chunks of [`Session::run_chunked`] written one
    /// after the other give the whole result's file, byte for byte.
    pub fn write_mesh(&self, mesh: &mut crate::export::MeshStream) -> std::io::Result<()> {
        let grid = |t: &Tessellation,
                    g: usize,
                    local: &[[u32; 3]],
                    mesh: &mut crate::export::MeshStream| {
            let r = g * t.grid_len()..(g + 1) * t.grid_len();
            mesh.patch(&t.positions[r.clone()], &t.normals[r], local)
        };
        match self {
            Output::Grid(t) => {
                let local = t.local_triangles();
                (0..t.faces).try_for_each(|g| grid(t, g, &local, mesh))
            }
            // Base face order, as the OBJ: sub-faces next to their quads.
            Output::Polygons(p) => {
                let (quad, sub) = (p.quads.local_triangles(), p.subfaces.local_triangles());
                p.base_order()
                    .into_iter()
                    .try_for_each(|(_, _, is_sub, g)| {
                        if is_sub {
                            grid(&p.subfaces, g, &sub, mesh)
                        } else {
                            grid(&p.quads, g, &quad, mesh)
                        }
                    })
            }
            Output::Instanced(a) => {
                let mut local: std::collections::BTreeMap<u32, Vec<[u32; 3]>> = Default::default();
                for g in 0..a.levels.len() {
                    let l = a.levels[g];
                    let tris = local.entry(l).or_insert_with(|| a.local_triangles(l));
                    let end = a.offsets.get(g + 1).copied().unwrap_or(a.positions.len());
                    let r = a.offsets[g]..end;
                    mesh.patch(&a.positions[r.clone()], &a.normals[r], tris)?;
                }
                Ok(())
            }
            Output::Captured(c) => c
                .patches
                .iter()
                .try_for_each(|p| mesh.patch(&p.positions, &p.normals, &p.triangles)),
        }
    }

    /// The first sample with a NaN or infinite position or normal, as
    /// `(face, sample within the output)`: the face is the base face of a
    /// grid (its `face_ids`), the patch of an instanced or captured result.
    /// [`Session::run`] turns one into [`Error::NonFiniteSample`], so a
    /// non-finite value is never handed on silently.
    pub fn first_non_finite(&self) -> Option<(usize, usize)> {
        let bad = |p: &glam::Vec3, n: &glam::Vec3| !(p.is_finite() && n.is_finite());
        let in_grid = |t: &Tessellation, base: usize| {
            let per = t.grid_len().max(1);
            (0..t.positions.len())
                .find(|&i| bad(&t.positions[i], &t.normals[i]))
                .map(|i| (t.face_of(i / per), base + i))
        };
        match self {
            Output::Grid(t) => in_grid(t, 0),
            Output::Polygons(p) => {
                in_grid(&p.quads, 0).or_else(|| in_grid(&p.subfaces, p.quads.positions.len()))
            }
            Output::Instanced(a) => (0..a.positions.len())
                .find(|&i| bad(&a.positions[i], &a.normals[i]))
                .map(|i| {
                    let g = a.offsets.partition_point(|&o| o <= i).saturating_sub(1);
                    (a.face_of(g), i)
                }),
            Output::Captured(c) => {
                let mut base = 0;
                for (k, patch) in c.patches.iter().enumerate() {
                    if let Some(i) = (0..patch.positions.len())
                        .find(|&i| bad(&patch.positions[i], &patch.normals[i]))
                    {
                        return Some((c.first_face + k, base + i));
                    }
                    base += patch.positions.len();
                }
                None
            }
        }
    }

    /// Exact-bit weld (see [`crate::check::weld`]).
    pub fn weld(&self) -> WeldReport {
        match self {
            Output::Grid(t) => crate::check::weld::weld(t),
            Output::Captured(c) => c.weld(),
            Output::Instanced(_) | Output::Polygons(_) => {
                let soup: Vec<Vec3> = self.triangles().into_iter().flatten().collect();
                crate::check::weld::weld_triangles(&soup, 3, &[[0, 1, 2]])
            }
        }
    }

    /// Open sample edges a watertight result keeps on the mesh's true
    /// boundary (docs/boundaries.md §5): one per segment of every base
    /// boundary edge of an emitting face and every edge next to a face that
    /// emits nothing, at that edge's own level. [`crate::weld::WeldReport::cracks`]
    /// of this count is 0 exactly when nothing else is open. Quad schemes
    /// (`topo` of the mesh tessellated); 0 for triangle schemes.
    pub fn boundary_open_edges(&self, topo: &crate::mesh::topology::Topology) -> usize {
        let open = crate::check::weld::open_base_halfedges(topo);
        match self {
            Output::Grid(t) if t.sides == 4 => t.level as usize * open.len(),
            Output::Instanced(a) if a.sides == 4 => open
                .iter()
                .map(|&h| a.edge_levels.get(h).copied().unwrap_or(0) as usize)
                .sum(),
            Output::Captured(c) => open
                .iter()
                .map(|&h| {
                    let (f, k) = (
                        topo.face[h] as usize,
                        h - topo.face_offsets[topo.face[h] as usize] as usize,
                    );
                    let patch = f.checked_sub(c.first_face).and_then(|k| c.patches.get(k));
                    patch.map_or(0, |p| {
                        // Captured vertices on local edge k (v = 0, u = 1, v = 1, u = 0).
                        let on = |d: &[f32; 3]| match k {
                            0 => d[1] == 0.0,
                            1 => d[0] == 1.0,
                            2 => d[1] == 1.0,
                            _ => d[0] == 0.0,
                        };
                        let mut pts: Vec<[u32; 2]> = p
                            .domain
                            .iter()
                            .filter(|d| on(d))
                            .map(|d| [d[0].to_bits(), d[1].to_bits()])
                            .collect();
                        pts.sort_unstable();
                        pts.dedup();
                        pts.len().saturating_sub(1)
                    })
                })
                .sum(),
            Output::Polygons(p) => p.boundary_open_edges,
            _ => 0,
        }
    }

    /// Samples (vertices) of the result: where the next chunk of a stream
    /// starts in the whole result.
    pub fn samples(&self) -> usize {
        match self {
            Output::Grid(t) => t.positions.len(),
            Output::Captured(c) => c.vertex_count(),
            Output::Instanced(a) => a.positions.len(),
            Output::Polygons(p) => p.quads.positions.len() + p.subfaces.positions.len(),
        }
    }

    /// `(patches, vertices, triangles)` for a summary line.
    pub fn counts(&self) -> (usize, usize, usize) {
        match self {
            Output::Grid(t) => (
                t.faces,
                t.positions.len(),
                t.faces * t.local_triangles().len(),
            ),
            Output::Captured(c) => (c.patches.len(), c.vertex_count(), c.triangle_count()),
            Output::Instanced(a) => (a.levels.len(), a.positions.len(), a.triangles().len()),
            Output::Polygons(p) => {
                let (q, s) = (&p.quads, &p.subfaces);
                (
                    q.faces + s.faces,
                    q.positions.len() + s.positions.len(),
                    q.faces * q.local_triangles().len() + s.faces * s.local_triangles().len(),
                )
            }
        }
    }
}

/// Every triangle of a grid tessellation as world positions.
fn grid_triangles(t: &Tessellation) -> Vec<[Vec3; 3]> {
    let (per, local) = (t.grid_len(), t.local_triangles());
    (0..t.faces)
        .flat_map(|f| {
            local
                .iter()
                .map(move |tri| tri.map(|k| t.positions[f * per + k as usize]))
        })
        .collect()
}

/// The devices a caller reuses across requests: each opened on first use.
#[derive(Default)]
pub struct Session {
    #[cfg(feature = "gpu")]
    gpu: Option<crate::gpu::wgpu::Gpu>,
    #[cfg(feature = "vulkan")]
    vulkan: Option<crate::gpu::vulkan::Vulkan>,
}

impl Session {
    pub fn new() -> Self {
        Self::default()
    }

    /// A session around a wgpu device the caller already has.
    #[cfg(feature = "gpu")]
    // the update fills `vulkan` when that feature is on
    #[allow(clippy::needless_update)]
    pub fn with_gpu(gpu: crate::gpu::wgpu::Gpu) -> Self {
        Session {
            gpu: Some(gpu),
            ..Self::default()
        }
    }

    /// The wgpu device, opened on first use (`TESSGEN_ADAPTER` picks one).
    #[cfg(feature = "gpu")]
    pub fn gpu(&mut self) -> Result<&crate::gpu::wgpu::Gpu, Error> {
        let gpu = match self.gpu.take() {
            Some(g) => g,
            None => crate::gpu::wgpu::Gpu::new()?,
        };
        Ok(self.gpu.insert(gpu))
    }

    /// The Vulkan device, opened on first use (`TESSGEN_VK_DEVICE` picks one).
    #[cfg(feature = "vulkan")]
    pub fn vulkan(&mut self) -> Result<&crate::gpu::vulkan::Vulkan, Error> {
        let vk = match self.vulkan.take() {
            Some(v) => v,
            None => crate::gpu::vulkan::Vulkan::new()?,
        };
        Ok(self.vulkan.insert(vk))
    }

    /// Validate `request` against `mesh`, then run it on its backend with
    /// this session's devices. Nothing is opened for a request that fails
    /// validation.
    pub fn tessellate(&mut self, mesh: &Mesh, request: &Request<'_>) -> Result<Output, Error> {
        let v = request.validate(mesh)?;
        self.run(&v)
    }

    /// Run a request validated by [`Request::validate`] (so a caller can
    /// also read [`Validated::notes`] and [`Validated::expected_open_edges`]).
    pub fn run(&mut self, v: &Validated<'_>) -> Result<Output, Error> {
        let out = backend::run(v, self)?;
        finite(v, &out, 0)?;
        // A refined mesh comes back in the base layout (its holes are left
        // out there); otherwise faces without a limit surface (holes;
        // boundary rule 0) are evaluated like any other (their vertices
        // shape the neighbours) but emit no grid (docs/boundaries.md §5).
        Ok(match (out, v.refined(), v.no_limit()) {
            (Output::Grid(t), Some(r), _) => {
                // The deeper depths of a feature-adaptive refinement run
                // like the first; the base grids take each sample from the
                // leaf that covers it.
                let mut runs = vec![t];
                for d in &v.deeper {
                    let out = backend::run(d, self)?;
                    finite(d, &out, 0)?;
                    match out {
                        Output::Grid(t) => runs.push(t),
                        _ => return Err(refined::RefineError::NotAGrid.into()),
                    }
                }
                let parts: Vec<refined::Part<'_>> = v
                    .parts()
                    .zip(&runs)
                    .map(|(p, t)| refined::Part {
                        domain: p.refined().unwrap_or(r),
                        t,
                        no_limit: p.topology().map_or(&[][..], |t| &t.no_limit[..]),
                    })
                    .collect();
                let mut out = refined::assemble(&parts)?;
                if let Output::Polygons(p) = &mut out {
                    p.boundary_open_edges = v.refined_open_edges();
                }
                out
            }
            (Output::Grid(mut t), None, Some(no_limit)) => {
                t.retain_faces(&emitting(no_limit));
                Output::Grid(t)
            }
            // Adaptive results are per face of the mesh run (the refined
            // one after a refinement): its holes drop out the same way.
            (Output::Instanced(mut a), _, Some(no_limit)) => {
                a.retain_faces(&emitting(no_limit));
                Output::Instanced(a)
            }
            (Output::Captured(mut c), _, Some(no_limit)) => {
                c.clear_patches(no_limit);
                Output::Captured(c)
            }
            (out, _, _) => out,
        })
    }
}

/// `keep` for `retain_faces` (and `cpu::evaluate_emitting`): the faces
/// with a limit surface.
pub(crate) fn emitting(no_limit: &[bool]) -> Vec<bool> {
    no_limit.iter().map(|&n| !n).collect()
}

/// The last line of defence (the magnitude check of [`Request::validate`]
/// is the first): a NaN or infinite sample of `out` is
/// [`Error::NonFiniteSample`] naming its face; `first_sample` is where
/// `out` starts in the whole result (a streamed chunk's offset).
fn finite(v: &Validated<'_>, out: &Output, first_sample: usize) -> Result<(), Error> {
    match out.first_non_finite() {
        None => Ok(()),
        Some((face, sample)) => Err(Error::NonFiniteSample {
            face,
            sample: first_sample + sample,
            scheme: v.kernels.name,
            backend: v.request.backend.name(),
        }),
    }
}

/// [`Session::tessellate`] with a fresh session (opens a device per call
/// on the GPU backends; keep a [`Session`] to reuse one).
pub fn tessellate(mesh: &Mesh, request: &Request<'_>) -> Result<Output, Error> {
    Session::new().tessellate(mesh, request)
}

/// [`Session::tessellate`], spelled as a function.
pub fn tessellate_with(
    mesh: &Mesh,
    request: &Request<'_>,
    session: &mut Session,
) -> Result<Output, Error> {
    session.tessellate(mesh, request)
}

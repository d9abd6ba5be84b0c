//! Running a [`Validated`] request on its backend: the one place that picks
//! the upload (quads or triangles, with or without displacement) and the
//! evaluation (uniform grid, instanced adaptive, hardware capture). No
//! check lives here: [`super::Request::validate`] made them all.

use super::request::{Domain, Validated};
use super::{Error, Output, Session};
use crate::cpu;
use crate::cpu::displace::DisplaceData;

/// Dispatch on the request's backend.
pub(crate) fn run(v: &Validated<'_>, session: &mut Session) -> Result<Output, Error> {
    use super::Backend;
    let _ = &session;
    match v.request.backend {
        Backend::Cpu => run_cpu(v),
        #[cfg(feature = "gpu")]
        Backend::Wgpu => run_wgpu(v, session.gpu()?),
        #[cfg(feature = "vulkan")]
        Backend::VulkanGlsl | Backend::VulkanHlsl => run_vulkan(v, session.vulkan()?),
    }
}

/// The uniform level of a validated request (adaptive requests have none).
/// A refined mesh runs its refined faces at the leaf level `N / 2ᵏ`.
fn level(v: &Validated<'_>) -> u32 {
    match (v.request.sampling.clone(), v.refined()) {
        (super::Sampling::Uniform(_), Some(r)) => r.leaf_level,
        (super::Sampling::Uniform(level), None) => level,
        (super::Sampling::Adaptive(_), _) => 0,
    }
}

/// A refined request's base positions and stencil table: the GPU backends
/// refine on the device (`refine_main`) from these, to the bits the CPU's
/// `StencilTable::apply` gave the refined mesh.
#[cfg(any(feature = "gpu", feature = "vulkan"))]
fn gpu_refined<'a>(
    v: &'a Validated<'_>,
) -> Option<(Vec<glam::Vec3>, &'a crate::mesh::refine::StencilTable)> {
    let r = v.refined()?;
    let base = v
        .mesh
        .positions
        .iter()
        .map(|&p| glam::Vec3::from(p))
        .collect();
    Some((base, &r.refinement.stencils))
}

/// The CPU patches of a request, in face order (quads or triangles).
pub(crate) fn cpu_patches(v: &Validated<'_>) -> Result<cpu::Patches, cpu::TessError> {
    match &v.domain {
        Domain::Quads { topo, positions } => cpu::construct(topo, positions, v.kernels),
        Domain::Triangles(tri) => cpu::construct_tri(tri, v.kernels),
    }
}

/// The displacement data of a displaced request for its CPU `patches`
/// (owners, texture coordinates and the map in the CPU layout).
pub(crate) fn cpu_displacement(
    v: &Validated<'_>,
    patches: &cpu::Patches,
) -> Result<Option<DisplaceData>, Error> {
    let Some(d) = v.request.displacement else {
        return Ok(None);
    };
    Ok(Some(match &v.domain {
        Domain::Quads { topo, .. } => cpu::displacement_data(v.run_mesh(), topo, patches, d)?,
        Domain::Triangles(tri) => cpu::displacement_data_tri(v.mesh, tri, patches, d)?,
    }))
}

/// The CPU: construct in face order, then the grid walk or the adaptive walk.
fn run_cpu(v: &Validated<'_>) -> Result<Output, Error> {
    let patches = cpu_patches(v)?;
    let data = cpu_displacement(v, &patches)?;
    let edges = v.domain.edges();
    Ok(match (&v.adaptive, &data) {
        // Faces that emit nothing (holes; a feature-adaptive depth's
        // non-leaves) are not evaluated on the CPU.
        (None, None) => Output::Grid(match v.no_limit() {
            Some(no_limit) => {
                cpu::evaluate_emitting(&patches, level(v), &super::emitting(no_limit))?
            }
            None => cpu::evaluate(&patches, level(v))?,
        }),
        (None, Some(d)) => Output::Grid(cpu::evaluate_displaced(&patches, level(v), d)?),
        (Some(a), None) => Output::Instanced(crate::cpu::adaptive::evaluate_cpu_adaptive(
            &patches,
            edges,
            &a.adaptive,
            a.max_level,
        )?),
        (Some(a), Some(d)) => {
            Output::Instanced(crate::cpu::adaptive::evaluate_cpu_adaptive_displaced(
                &patches,
                edges,
                &a.adaptive,
                a.max_level,
                d,
            )?)
        }
    })
}

/// wgpu: upload (displacement owners in the upload's class-sorted layout),
/// then `eval_main` read back, or the instanced adaptive buckets.
#[cfg(feature = "gpu")]
fn run_wgpu(v: &Validated<'_>, gpu: &crate::gpu::wgpu::Gpu) -> Result<Output, Error> {
    let m = wgpu_mesh(v, gpu)?;
    Ok(match &v.adaptive {
        None => Output::Grid(m.evaluate(level(v))?),
        Some(a) => {
            Output::Instanced(m.evaluate_adaptive(v.domain.edges(), &a.adaptive, a.max_level)?)
        }
    })
}

/// The request's mesh on the wgpu device, constructed.
#[cfg(feature = "gpu")]
pub(crate) fn wgpu_mesh<'g>(
    v: &Validated<'_>,
    gpu: &'g crate::gpu::wgpu::Gpu,
) -> Result<crate::gpu::wgpu::GpuMesh<'g>, Error> {
    use crate::gpu::wgpu::GpuMesh;
    let name = v.kernels.name;
    let displaced = v.request.displacement.map(|d| (v.run_mesh(), d));
    let m = match (&v.domain, v.request.displacement, gpu_refined(v)) {
        (Domain::Quads { topo, .. }, _, Some((base, stencils))) => {
            GpuMesh::new_refined(gpu, topo, &base, stencils, name, displaced)?
        }
        (Domain::Quads { topo, positions }, None, None) => {
            GpuMesh::new(gpu, topo, positions, name)?
        }
        (Domain::Quads { topo, positions }, Some(d), None) => {
            GpuMesh::new_displaced(gpu, v.run_mesh(), topo, positions, name, d)?
        }
        (Domain::Triangles(tri), None, _) => GpuMesh::new_tri(gpu, tri, name)?,
        (Domain::Triangles(tri), Some(d), _) => {
            GpuMesh::new_tri_displaced(gpu, v.mesh, tri, name, d)?
        }
    };
    Ok(m)
}

/// The Vulkan harness: quad schemes at a uniform level read back as grids
/// (the tessellator's quad pattern is the integer grid); triangle schemes
/// and adaptive draws as the captured triangles. Displacement builds the
/// evaluation stage with `TESSGEN_DISPLACE` (inside `VkMesh::new_displaced`).
#[cfg(feature = "vulkan")]
fn run_vulkan(v: &Validated<'_>, vk: &crate::gpu::vulkan::Vulkan) -> Result<Output, Error> {
    let m = vk_mesh(v, vk)?;
    Ok(match (&v.adaptive, &v.domain) {
        (Some(_), _) => Output::Captured(m.evaluate_adaptive()?),
        (None, Domain::Quads { .. }) => Output::Grid(m.evaluate(level(v))?),
        (None, Domain::Triangles(_)) => Output::Captured(m.evaluate_triangles(level(v))?),
    })
}

/// The request's mesh in the Vulkan harness, its pipelines built for the
/// request's options in the backend's language (HLSL or GLSL).
#[cfg(feature = "vulkan")]
pub(crate) fn vk_mesh<'v>(
    v: &Validated<'_>,
    vk: &'v crate::gpu::vulkan::Vulkan,
) -> Result<crate::gpu::vulkan::VkMesh<'v>, Error> {
    use crate::gpu::vulkan::{Language, Options, VkMesh};
    let language = match v.request.backend {
        super::Backend::VulkanHlsl => Language::Hlsl,
        _ => Language::Glsl,
    };
    let options = Options {
        adaptive: v.adaptive.as_ref().map(|a| a.adaptive.clone()),
        ..Options::new(language)
    };
    let name = v.kernels.name;
    let displaced = v.request.displacement.map(|d| (v.run_mesh(), d));
    let m = match (&v.domain, v.request.displacement, gpu_refined(v)) {
        (Domain::Quads { topo, .. }, _, Some((base, stencils))) => {
            VkMesh::new_refined(vk, topo, &base, stencils, name, displaced, &options)?
        }
        (Domain::Quads { topo, positions }, None, None) => {
            VkMesh::new(vk, topo, positions, name, &options)?
        }
        (Domain::Quads { topo, positions }, Some(d), None) => {
            VkMesh::new_displaced(vk, v.run_mesh(), topo, positions, name, d, &options)?
        }
        (Domain::Triangles(tri), None, _) => VkMesh::new_tri(vk, tri, name, &options)?,
        (Domain::Triangles(tri), Some(d), _) => {
            VkMesh::new_tri_displaced(vk, v.mesh, tri, name, d, &options)?
        }
    };
    Ok(m)
}

/// The session's device for a backend, opened (on first use): what the
/// grid sources of one request's depths share.
#[derive(Clone, Copy)]
pub(crate) enum Device<'s> {
    /// The CPU holds nothing of the session (this keeps `'s` used without
    /// GPU features).
    Cpu(std::marker::PhantomData<&'s ()>),
    #[cfg(feature = "gpu")]
    Wgpu(&'s crate::gpu::wgpu::Gpu),
    #[cfg(feature = "vulkan")]
    Vulkan(&'s crate::gpu::vulkan::Vulkan),
}

/// Opens `backend`'s device in `session` (reused if open).
pub(crate) fn device(session: &mut Session, backend: super::Backend) -> Result<Device<'_>, Error> {
    use super::Backend;
    let _ = &session;
    Ok(match backend {
        Backend::Cpu => Device::Cpu(std::marker::PhantomData),
        #[cfg(feature = "gpu")]
        Backend::Wgpu => Device::Wgpu(session.gpu()?),
        #[cfg(feature = "vulkan")]
        Backend::VulkanGlsl | Backend::VulkanHlsl => Device::Vulkan(session.vulkan()?),
    })
}

/// A uniform grid request, constructed (uploaded) once and then evaluated
/// window by window of faces: the streamed form of [`run`]
/// (`Session::run_chunked`). Each window's samples are [`run`]'s.
// One per stream, made once: the variants' sizes do not matter.
#[allow(clippy::large_enum_variant)]
pub(crate) enum GridSource<'s> {
    Cpu {
        patches: cpu::Patches,
        displace: Option<DisplaceData>,
        /// The GPU variants borrow the session's device for `'s`; the CPU
        /// holds nothing of it (this keeps `'s` used without GPU features).
        device: std::marker::PhantomData<&'s ()>,
    },
    #[cfg(feature = "gpu")]
    Wgpu(crate::gpu::wgpu::GpuMesh<'s>),
    #[cfg(feature = "vulkan")]
    Vulkan(crate::gpu::vulkan::VkMesh<'s>),
}

impl GridSource<'_> {
    /// Whether the request's result is one uniform grid per face of the
    /// request's mesh, i.e. has a grid source: not for adaptive requests,
    /// refined meshes (assembled from several runs), or triangle schemes on
    /// the Vulkan harness (captured triangles).
    pub(crate) fn streams(v: &Validated<'_>) -> bool {
        // The hardware tessellator (the Vulkan harness) captures a triangle
        // scheme's triangles: not a grid.
        let captured =
            v.request.backend.hardware_tessellator() && matches!(v.domain, Domain::Triangles(_));
        v.adaptive.is_none() && v.refined().is_none() && !captured
    }

    /// The request's grid source: the mesh it runs (a refined request's
    /// refined mesh) constructed or uploaded, for a request whose result
    /// is one grid per face of it ([`Self::streams`], or one depth of a
    /// refinement, assembled per window by the caller).
    pub(crate) fn new<'s>(
        v: &Validated<'_>,
        session: &'s mut Session,
    ) -> Result<GridSource<'s>, Error> {
        GridSource::on(v, device(session, v.request.backend)?)
    }

    /// [`Self::new`] on a device already opened: the depths of a
    /// feature-adaptive refinement share one, as [`run`] runs them.
    pub(crate) fn on<'s>(v: &Validated<'_>, device: Device<'s>) -> Result<GridSource<'s>, Error> {
        Ok(match device {
            Device::Cpu(device) => {
                let patches = cpu_patches(v)?;
                let displace = cpu_displacement(v, &patches)?;
                GridSource::Cpu {
                    patches,
                    displace,
                    device,
                }
            }
            #[cfg(feature = "gpu")]
            Device::Wgpu(gpu) => GridSource::Wgpu(wgpu_mesh(v, gpu)?),
            #[cfg(feature = "vulkan")]
            Device::Vulkan(vk) => GridSource::Vulkan(vk_mesh(v, vk)?),
        })
    }

    /// Samples per chunk when the caller gives no bound: [`CHUNK_SAMPLES`]
    /// on the CPU, a quarter of it on a GPU, whose chunk is held up to four
    /// times on the host at once (the window, the samples and staging
    /// buffers — host memory on a software adapter —, the decoded
    /// readback).
    ///
    /// [`CHUNK_SAMPLES`]: super::CHUNK_SAMPLES
    pub(crate) fn chunk_samples(&self) -> usize {
        match self {
            GridSource::Cpu { .. } => super::CHUNK_SAMPLES,
            #[cfg(feature = "gpu")]
            GridSource::Wgpu(_) => super::CHUNK_SAMPLES / 4,
            #[cfg(feature = "vulkan")]
            GridSource::Vulkan(_) => super::CHUNK_SAMPLES / 4,
        }
    }

    /// Faces of the mesh evaluated (one grid each, holes included).
    pub(crate) fn faces(&self) -> usize {
        match self {
            GridSource::Cpu { patches, .. } => patches.face_class.len(),
            #[cfg(feature = "gpu")]
            GridSource::Wgpu(m) => m.patch_faces.len(),
            #[cfg(feature = "vulkan")]
            GridSource::Vulkan(m) => m.patch_faces.len(),
        }
    }

    /// The grids of the faces in `runs` (disjoint ranges) into `t`, one
    /// after the other (`face_ids` naming them), `scratch` holding each
    /// further run on a GPU. The CPU evaluates only the faces with
    /// `keep(face)` (those that emit, as [`run`] does: a feature-adaptive
    /// depth's ring-only faces are left out; a halo's border leaves); the
    /// GPUs dispatch whole runs. Each face's samples are [`run`]'s.
    pub(crate) fn evaluate_runs(
        &self,
        level: u32,
        runs: &[std::ops::Range<usize>],
        keep: &dyn Fn(usize) -> bool,
        t: &mut cpu::Tessellation,
        scratch: &mut cpu::Tessellation,
    ) -> Result<(), Error> {
        if let GridSource::Cpu {
            patches,
            displace: None,
            ..
        } = self
        {
            let faces: Vec<u32> = runs
                .iter()
                .flat_map(|r| r.clone())
                .filter(|&f| keep(f))
                .map(|f| f as u32)
                .collect();
            cpu::evaluate_listed_into(patches, level, &faces, t)?;
            return Ok(());
        }
        let per = match self {
            GridSource::Cpu { patches, .. } => (patches.scheme.grid_len)(level),
            #[cfg(feature = "gpu")]
            GridSource::Wgpu(m) => (m.scheme.grid_len)(level),
            #[cfg(feature = "vulkan")]
            GridSource::Vulkan(m) => (m.scheme.grid_len)(level),
        } as usize;
        let total: usize = runs.iter().map(|r| r.len() * per).sum();
        let mut runs = runs.iter().filter(|r| !r.is_empty());
        let Some(first) = runs.next() else {
            t.faces = 0;
            t.level = level;
            t.positions.clear();
            t.normals.clear();
            t.face_ids.clear();
            return Ok(());
        };
        self.evaluate(level, first.clone(), t)?;
        cpu::reserve_samples(&mut t.positions, &mut t.normals, total)?;
        for run in runs {
            self.evaluate(level, run.clone(), scratch)?;
            t.positions.extend_from_slice(&scratch.positions);
            t.normals.extend_from_slice(&scratch.normals);
            t.face_ids.extend_from_slice(&scratch.face_ids);
            t.faces += scratch.faces;
        }
        Ok(())
    }

    /// The grids of the faces `faces` into `t` (`face_ids` = the range),
    /// its buffers reused where the backend writes in place.
    pub(crate) fn evaluate(
        &self,
        level: u32,
        faces: std::ops::Range<usize>,
        t: &mut cpu::Tessellation,
    ) -> Result<(), Error> {
        match self {
            GridSource::Cpu {
                patches,
                displace: None,
                ..
            } => cpu::evaluate_faces_into(patches, level, faces, t)?,
            GridSource::Cpu {
                patches,
                displace: Some(d),
                ..
            } => *t = cpu::evaluate_displaced_faces(patches, level, d, faces)?,
            #[cfg(feature = "gpu")]
            GridSource::Wgpu(m) => *t = m.evaluate_faces(level, faces)?,
            #[cfg(feature = "vulkan")]
            GridSource::Vulkan(m) => *t = m.evaluate_faces(level, faces)?,
        }
        Ok(())
    }
}

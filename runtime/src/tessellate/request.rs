//! What to tessellate and where: a [`Request`], checked once against the
//! mesh by [`Request::validate`] into a [`Validated`] request that every
//! backend runs without checking again.
//!
//! Every refusal is one [`Error`] variant raised here, before any device
//! is opened, so a wrong flag costs no GPU start-up and every backend
//! refuses the same things with the same words.

use super::refined::RefinedDomain;
use crate::cpu::adaptive::{self, Adaptive, AdaptiveMesh, Metric, Partitioning};
use crate::cpu::displace::{DisplaceError, Displacement};
use crate::cpu::{self, TessError, MAX_LEVEL};
use crate::kernels::common::SchemeKernels;
use crate::mesh::features::Features;
use crate::mesh::tags::TagFile;
use crate::mesh::topology::Topology;
use crate::mesh::trimesh::TriMesh;
use crate::mesh::Mesh;
use glam::Vec3;

/// Where the generated code runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Backend {
    /// The generated Rust kernels, in parallel on the CPU.
    #[default]
    Cpu,
    /// The generated WGSL through wgpu (compute construction and evaluation).
    #[cfg(feature = "gpu")]
    Wgpu,
    /// The emitted GLSL tessellation shaders in the Vulkan harness.
    #[cfg(feature = "vulkan")]
    VulkanGlsl,
    /// The emitted HLSL hull/domain shaders in the Vulkan harness.
    #[cfg(feature = "vulkan")]
    VulkanHlsl,
}

impl Backend {
    /// The name the CLI's `--backend` uses.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            #[cfg(feature = "gpu")]
            Backend::Wgpu => "wgpu",
            #[cfg(feature = "vulkan")]
            Backend::VulkanGlsl => "glsl",
            #[cfg(feature = "vulkan")]
            Backend::VulkanHlsl => "hlsl",
        }
    }

    /// Whether adaptive factors go to a hardware tessellator (any
    /// partitioning) rather than the instanced path (power-of-two levels).
    pub fn hardware_tessellator(self) -> bool {
        match self {
            Backend::Cpu => false,
            #[cfg(feature = "gpu")]
            Backend::Wgpu => false,
            #[cfg(feature = "vulkan")]
            Backend::VulkanGlsl | Backend::VulkanHlsl => true,
        }
    }
}

/// The per-edge metric of an adaptive request. Random factors need the
/// number of edges, which only the mesh the scheme runs on (quad topology
/// or triangle mesh) knows, so they are drawn at validation.
#[derive(Clone, Debug, PartialEq)]
pub enum EdgeMetric {
    /// [`adaptive::random_factors`]`(edges, seed, lo, hi)`.
    Random { seed: u64, lo: f32, hi: f32 },
    /// A metric as given (screen, distance, explicit factors).
    Given(Metric),
}

/// Adaptive tessellation: one factor per edge.
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveRequest {
    pub metric: EdgeMetric,
    /// Fractional partitioning only on a hardware tessellator.
    pub partitioning: Partitioning,
    /// Largest factor: the hardware tessellator clamps to it; the instanced
    /// path rounds it down to a power of two ([`power_of_two_level`]).
    pub max_factor: f32,
}

/// How densely to sample.
#[derive(Clone, Debug, PartialEq)]
pub enum Sampling {
    /// Every face at one level: `(N+1)²` samples per quad.
    Uniform(u32),
    Adaptive(AdaptiveRequest),
}

/// One tessellation request: scheme, sampling, backend and options.
/// Build with [`Request::uniform`] or [`Request::adaptive`] and the
/// builder methods; the displacement map and tags are borrowed (maps are
/// large and a caller often runs several requests with one).
#[derive(Clone, Debug)]
pub struct Request<'a> {
    pub scheme: String,
    pub sampling: Sampling,
    pub backend: Backend,
    pub displacement: Option<&'a Displacement>,
    /// `stpn`'s crease tags ([`crate::mesh::tags`]).
    pub tags: Option<&'a TagFile>,
    /// Triangle schemes on a quad mesh: split each quad along v0–v2.
    pub split_quads: bool,
    /// Most Catmull-Clark steps spent on semi-sharp creases
    /// ([`super::refined`]; default [`super::refined::DEFAULT_CREASE_REFINEMENT`],
    /// 0 applies them as infinitely sharp).
    pub crease_refinement: u32,
    /// Catmull-Clark steps around extraordinary vertices before the scheme
    /// takes over (OpenSubdiv's isolation level; default 0: the scheme
    /// approximates every extraordinary face). Uniform sampling, schemes
    /// with an extraordinary class.
    pub isolate: u32,
    /// Refine into one mesh (uniform Catmull-Clark steps, at most
    /// [`crate::mesh::refine::UNIFORM_CREASE_REFINEMENT`] for creases)
    /// instead of feature-adaptive depths: what a renderer that draws one
    /// patch per face of the mesh run needs (depths meeting would show
    /// T-junctions). Adaptive sampling always refines so.
    pub one_mesh: bool,
}

impl<'a> Request<'a> {
    /// `scheme` at a uniform `level`, on the CPU.
    pub fn uniform(scheme: &str, level: u32) -> Self {
        Self::new(scheme, Sampling::Uniform(level))
    }

    /// `scheme` adaptively, on the CPU.
    pub fn adaptive(scheme: &str, adaptive: AdaptiveRequest) -> Self {
        Self::new(scheme, Sampling::Adaptive(adaptive))
    }

    fn new(scheme: &str, sampling: Sampling) -> Self {
        Request {
            scheme: scheme.into(),
            sampling,
            backend: Backend::Cpu,
            displacement: None,
            tags: None,
            split_quads: false,
            crease_refinement: super::refined::DEFAULT_CREASE_REFINEMENT,
            isolate: 0,
            one_mesh: false,
        }
    }

    /// See [`Request::one_mesh`].
    pub fn one_mesh(mut self, yes: bool) -> Self {
        self.one_mesh = yes;
        self
    }

    /// At most `steps` Catmull-Clark steps for semi-sharp creases.
    pub fn crease_refinement(mut self, steps: u32) -> Self {
        self.crease_refinement = steps;
        self
    }

    /// `steps` Catmull-Clark steps around extraordinary vertices (at most
    /// [`crate::mesh::refine::MAX_REFINE_LEVELS`], and what the level
    /// allows: [`super::refined::depth_cap`]).
    pub fn isolate(mut self, steps: u32) -> Self {
        self.isolate = steps;
        self
    }

    /// Whether `kernels` can run the partial meshes of a feature-adaptive
    /// refinement (its irregular rim): schemes with an extraordinary class.
    fn has_extraordinary_class(kernels: &SchemeKernels) -> bool {
        kernels.classes.iter().any(|c| c.class == "extraordinary")
    }

    /// Uniform sampling with a scheme that refines feature-adaptively.
    fn refines_adaptively(&self, kernels: &SchemeKernels) -> bool {
        matches!(self.sampling, Sampling::Uniform(_))
            && !self.one_mesh
            && Self::has_extraordinary_class(kernels)
    }

    pub fn on(mut self, backend: Backend) -> Self {
        self.backend = backend;
        self
    }

    pub fn displaced(mut self, d: &'a Displacement) -> Self {
        self.displacement = Some(d);
        self
    }

    pub fn tagged(mut self, tags: &'a TagFile) -> Self {
        self.tags = Some(tags);
        self
    }

    pub fn split_quads(mut self, split: bool) -> Self {
        self.split_quads = split;
        self
    }

    /// Check the request against `mesh`, once, and build what every
    /// backend starts from (the quad topology or the triangle mesh, the
    /// resolved adaptive settings). In this order: scheme, level, tags,
    /// partitioning, the largest adaptive factor, the mesh for the scheme
    /// (quads vs triangles, split quads, tag file, patch classes), texture
    /// coordinates.
    pub fn validate<'r>(&'r self, mesh: &'r Mesh) -> Result<Validated<'r>, Error> {
        let kernels = crate::kernels::scheme(&self.scheme).ok_or_else(|| Error::UnknownScheme {
            name: self.scheme.clone(),
            available: crate::kernels::scheme_names().join(", "),
        })?;
        if let Sampling::Uniform(level) = self.sampling {
            if level == 0 || level > MAX_LEVEL {
                return Err(Error::Level { level });
            }
        }
        if self.tags.is_some() && kernels.name != "stpn" {
            return Err(Error::TagsUnused {
                scheme: kernels.name.into(),
            });
        }
        if self.tags.is_some() && self.displacement.is_some() {
            return Err(Error::TagsWithDisplacement);
        }
        if let Sampling::Adaptive(a) = &self.sampling {
            if a.partitioning != Partitioning::Integer && !self.backend.hardware_tessellator() {
                return Err(Error::Partitioning {
                    backend: self.backend.name(),
                    partitioning: a.partitioning,
                });
            }
            // Factors are clamped to [1, max_factor]: a NaN, infinite or
            // sub-1 largest factor is no range (a NaN once reached the
            // hardware tessellator as level 65536).
            if !(a.max_factor.is_finite() && a.max_factor >= 1.0) {
                return Err(adaptive::AdaptiveError::Clamp {
                    min: 1.0,
                    max: a.max_factor,
                }
                .into());
            }
        }
        // Before anything is evaluated: sizes f32 evaluation cannot take.
        mesh.check_magnitude()?;
        let mut refined: Option<Box<RefinedDomain>> = None;
        let mut deeper: Vec<Validated<'r>> = Vec::new();
        let mut notes: Vec<String> = Vec::new();
        let domain = if kernels.sides == 3 {
            if let Ok((_, warnings)) = Features::from_mesh(mesh) {
                notes = warnings.iter().map(|w| w.to_string()).collect();
            }
            Domain::Triangles(cpu::tri_mesh(mesh, self.split_quads, self.tags)?)
        } else {
            mesh.validate()?;
            let (features, warnings) = Features::from_mesh(mesh)
                .map_err(|e| TessError::from(crate::mesh::topology::TopologyError::from(e)))?;
            let level = match self.sampling {
                Sampling::Uniform(n) => Some(n),
                Sampling::Adaptive(_) => None,
            };
            let opts = cpu::topology_options();
            let feature_adaptive = self.refines_adaptively(kernels);
            let refine = super::refined::RefineOptions {
                level,
                crease_cap: self.crease_refinement,
                isolate: self.isolate,
                max_valence: opts.max_valence,
                feature_adaptive,
            };
            let mut parts =
                RefinedDomain::for_mesh(mesh, &features, &warnings, &refine)?.into_iter();
            refined = parts.next().map(Box::new);
            let topo = match &refined {
                Some(r) => refined_topology(r, kernels)?,
                None => {
                    let mut topo =
                        Topology::build_with(mesh, &opts, &features).map_err(TessError::from)?;
                    notes = warnings.iter().map(|w| w.to_string()).collect();
                    topo.warnings = warnings;
                    cpu::face_classes(&topo, kernels)?;
                    topo
                }
            };
            let run_mesh = refined.as_ref().map_or(mesh, |r| &r.refinement.mesh);
            // Deeper depths of a feature-adaptive refinement: each its own
            // run of the same request (uniform, so nothing else to resolve).
            for part in parts {
                let topo = refined_topology(&part, kernels)?;
                let positions = part
                    .refinement
                    .mesh
                    .positions
                    .iter()
                    .map(|p| Vec3::from_array(*p))
                    .collect();
                deeper.push(Validated {
                    request: self,
                    mesh,
                    kernels,
                    domain: Domain::Quads {
                        topo: Box::new(topo),
                        positions,
                    },
                    adaptive: None,
                    refined: Some(Box::new(part)),
                    notes: Vec::new(),
                    deeper: Vec::new(),
                });
            }
            let positions = run_mesh
                .positions
                .iter()
                .map(|p| Vec3::from_array(*p))
                .collect();
            Domain::Quads {
                topo: Box::new(topo),
                positions,
            }
        };
        if self.displacement.is_some() {
            texcoords_everywhere(mesh)?;
        }
        let adaptive = match &self.sampling {
            Sampling::Uniform(_) => None,
            Sampling::Adaptive(a) => Some(self.resolve(a, &domain)),
        };
        if let Some(r) = &refined {
            notes.clone_from(&r.notes);
        }
        if self.isolate > 0 && !(kernels.sides == 4 && self.refines_adaptively(kernels)) {
            notes.push(format!(
                "isolation ({} steps) not applied: it takes a uniform level and a quad scheme \
                 with an extraordinary class (not {}{})",
                self.isolate,
                self.scheme,
                if matches!(self.sampling, Sampling::Adaptive(_)) {
                    ", adaptive"
                } else {
                    ""
                }
            ));
        }
        Ok(Validated {
            request: self,
            mesh,
            kernels,
            domain,
            adaptive,
            refined,
            notes,
            deeper,
        })
    }

    /// The adaptive settings a backend runs with: the instanced path at
    /// power-of-two levels up to `max_factor` rounded down, integer
    /// partitioning; the hardware tessellator clamped to `max_factor`.
    fn resolve(&self, a: &AdaptiveRequest, domain: &Domain) -> Resolved {
        let metric = match &a.metric {
            EdgeMetric::Random { seed, lo, hi } => {
                let edges = domain.edges().edge_ids().1;
                Metric::Buffer(adaptive::random_factors(edges, *seed, *lo, *hi))
            }
            EdgeMetric::Given(m) => m.clone(),
        };
        if self.backend.hardware_tessellator() {
            Resolved {
                adaptive: Adaptive {
                    metric,
                    partitioning: a.partitioning,
                    min: 1.0,
                    max: a.max_factor,
                },
                max_level: 0,
            }
        } else {
            let max_level = power_of_two_level(a.max_factor);
            Resolved {
                adaptive: Adaptive {
                    metric,
                    partitioning: Partitioning::Integer,
                    min: 1.0,
                    max: max_level as f32,
                },
                max_level,
            }
        }
    }
}

/// `max_factor` rounded down to a power of two, within `1..=MAX_LEVEL`:
/// the instanced path's largest bucket level.
pub fn power_of_two_level(max_factor: f32) -> u32 {
    let mut max_level = 1u32;
    while max_level * 2 <= max_factor.clamp(1.0, MAX_LEVEL as f32) as u32 {
        max_level *= 2;
    }
    max_level
}

/// Displacement samples the map at every face corner's `vt`: the first
/// corner without one (file order) is the error.
fn texcoords_everywhere(mesh: &Mesh) -> Result<(), Error> {
    for face in 0..mesh.num_faces() {
        let first = mesh.face_offsets[face] as usize;
        for corner in 0..mesh.face(face).len() {
            if mesh.corner_texcoord(first + corner).is_none() {
                return Err(DisplaceError::MissingTexCoord { face, corner }.into());
            }
        }
    }
    Ok(())
}

/// What a scheme runs on: quad schemes the half-edge topology, triangle
/// schemes the triangle mesh (split quads, normals, crease tags).
#[derive(Debug)]
pub(crate) enum Domain {
    Quads {
        /// Boxed: the topology's arrays make this variant much larger than the other.
        topo: Box<Topology>,
        positions: Vec<Vec3>,
    },
    Triangles(TriMesh),
}

impl Domain {
    pub(crate) fn edges(&self) -> AdaptiveMesh<'_> {
        match self {
            Domain::Quads { topo, .. } => topo.as_ref().into(),
            Domain::Triangles(t) => t.into(),
        }
    }
}

/// Adaptive settings resolved for the backend; `max_level` is the
/// instanced path's largest bucket (0 on the hardware tessellator).
#[derive(Debug)]
pub(crate) struct Resolved {
    pub(crate) adaptive: Adaptive,
    pub(crate) max_level: u32,
}

/// A request that passed [`Request::validate`] for one mesh.
#[derive(Debug)]
pub struct Validated<'r> {
    pub(crate) request: &'r Request<'r>,
    pub(crate) mesh: &'r Mesh,
    pub(crate) kernels: &'static SchemeKernels,
    pub(crate) domain: Domain,
    pub(crate) adaptive: Option<Resolved>,
    /// The refinement the quad schemes run on, if the mesh needed one.
    pub(crate) refined: Option<Box<RefinedDomain>>,
    pub(crate) notes: Vec<String>,
    /// The deeper depths of a feature-adaptive refinement, each run like
    /// this one and assembled with it.
    pub(crate) deeper: Vec<Validated<'r>>,
}

impl Validated<'_> {
    /// Per face, whether it has no limit surface and emits nothing (quad
    /// schemes; `None` when every face emits).
    pub(crate) fn no_limit(&self) -> Option<&[bool]> {
        match &self.domain {
            Domain::Quads { topo, .. } if topo.no_limit.iter().any(|&n| n) => Some(&topo.no_limit),
            _ => None,
        }
    }

    /// The refinement this request runs on (non-quads, semi-sharp creases).
    pub fn refined(&self) -> Option<&RefinedDomain> {
        self.refined.as_deref()
    }

    /// The mesh the backend evaluates: the refined mesh, or the input.
    pub fn run_mesh(&self) -> &Mesh {
        self.refined
            .as_ref()
            .map_or(self.mesh, |r| &r.refinement.mesh)
    }

    /// The quad topology the backend runs on (refined if refined).
    pub fn topology(&self) -> Option<&Topology> {
        match &self.domain {
            Domain::Quads { topo, .. } => Some(topo),
            Domain::Triangles(_) => None,
        }
    }

    /// Tag warnings and refinement notes, each one line: what is not
    /// applied exactly as written (never silently).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// Open sample edges a watertight result of this request keeps on the
    /// mesh's true boundary (see [`super::Output::boundary_open_edges`]);
    /// a crack is any open edge beyond them.
    pub fn expected_open_edges(&self, out: &super::Output) -> usize {
        match (self.topology(), &self.request.sampling, out) {
            (_, _, super::Output::Polygons(p)) => p.boundary_open_edges,
            (Some(_), Sampling::Uniform(_), _) if self.refined.is_some() => {
                self.refined_open_edges()
            }
            (Some(topo), _, out) => out.boundary_open_edges(topo),
            (None, _, _) => 0,
        }
    }

    /// Uniform refined runs: base boundary (and hole) half-edges × `N`.
    pub(crate) fn refined_open_edges(&self) -> usize {
        self.refined
            .as_ref()
            .map_or(0, |r| r.open_base_halfedges * r.level as usize)
    }

    /// Every depth this request runs: itself, then the deeper depths of a
    /// feature-adaptive refinement.
    pub fn parts(&self) -> impl Iterator<Item = &Validated<'_>> {
        std::iter::once(self).chain(self.deeper.iter())
    }

    /// The scheme's generated kernels.
    pub fn kernels(&self) -> &'static SchemeKernels {
        self.kernels
    }

    /// The request it was validated from.
    pub fn request(&self) -> &Request<'_> {
        self.request
    }

    /// The adaptive settings the backend runs with (`None` when uniform).
    pub fn adaptive(&self) -> Option<&Adaptive> {
        self.adaptive.as_ref().map(|r| &r.adaptive)
    }
}

/// Everything the front door refuses or its backends report.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("unknown scheme `{name}` (available: {available})")]
    UnknownScheme { name: String, available: String },
    #[error("tessellation level must be in 1..={max}, got {level}", max = MAX_LEVEL)]
    Level { level: u32 },
    #[error("scheme `{scheme}` takes no crease tags (only `stpn` reads them)")]
    TagsUnused { scheme: String },
    #[error("displacement takes no crease tags (--displace does not take --tags)")]
    TagsWithDisplacement,
    #[error(
        "--backend {backend} snaps to power-of-two levels: --partitioning integer only \
         (got {partitioning:?}; fractional partitioning needs the hardware tessellator, glsl or hlsl)"
    )]
    Partitioning {
        backend: &'static str,
        partitioning: Partitioning,
    },
    #[error(
        "face {face}: sample {sample} came out NaN or infinite ({scheme} on {backend}); nothing \
         was written. Please report it with the mesh"
    )]
    NonFiniteSample {
        face: usize,
        sample: usize,
        scheme: &'static str,
        backend: &'static str,
    },
    #[error(transparent)]
    Refine(#[from] super::refined::RefineError),
    #[error(transparent)]
    Tess(#[from] TessError),
    #[error(transparent)]
    Mesh(#[from] crate::mesh::MeshError),
    #[error(transparent)]
    Adaptive(#[from] adaptive::AdaptiveError),
    #[cfg(feature = "gpu")]
    #[error(transparent)]
    Gpu(#[from] crate::gpu::wgpu::GpuError),
    #[cfg(feature = "vulkan")]
    #[error(transparent)]
    Vulkan(#[from] crate::gpu::vulkan::VkError),
}

impl From<DisplaceError> for Error {
    fn from(e: DisplaceError) -> Self {
        Error::Tess(TessError::Displace(e))
    }
}

/// The topology of one refined depth, with the scheme's classes checked
/// on the faces that emit (a `regular` face error names the base face).
fn refined_topology(r: &RefinedDomain, kernels: &'static SchemeKernels) -> Result<Topology, Error> {
    let opts = cpu::topology_options();
    let topo = Topology::build_with(&r.refinement.mesh, &opts, &r.refinement.features)
        .map_err(TessError::from)?;
    cpu::face_classes(&topo, kernels).map_err(|e| match e {
        TessError::ExtraordinaryFace { scheme, face } => TessError::ExtraordinaryFace {
            scheme,
            face: r.base_face(face),
        },
        e => e,
    })?;
    Ok(topo)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpu::displace::{DisplaceMap, Ownership};

    fn mesh(obj: &str) -> Mesh {
        Mesh::from_obj_str(obj).expect("mesh")
    }

    /// A closed cube of six quads (every corner valence 3).
    fn cube(with_vt: bool) -> Mesh {
        let mut s = String::from(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n",
        );
        let faces = [
            [1, 4, 3, 2],
            [5, 6, 7, 8],
            [1, 2, 6, 5],
            [2, 3, 7, 6],
            [3, 4, 8, 7],
            [4, 1, 5, 8],
        ];
        if with_vt {
            s.push_str("vt 0 0\n");
        }
        for f in faces {
            let c: Vec<String> = f
                .iter()
                .map(|v| {
                    if with_vt {
                        format!("{v}/1")
                    } else {
                        v.to_string()
                    }
                })
                .collect();
            s.push_str(&format!("f {}\n", c.join(" ")));
        }
        mesh(&s)
    }

    fn displacement() -> Displacement {
        Displacement {
            map: DisplaceMap::flat(),
            scale: 0.5,
            ownership: Ownership::LowestFace,
        }
    }

    fn adaptive(partitioning: Partitioning) -> AdaptiveRequest {
        AdaptiveRequest {
            metric: EdgeMetric::Random {
                seed: 7,
                lo: 1.0,
                hi: 4.0,
            },
            partitioning,
            max_factor: 8.0,
        }
    }

    fn tags(m: &Mesh) -> TagFile {
        TagFile::parse(
            "tag 1 tension 0.5\n",
            m.num_vertices(),
            m.num_faces(),
            |f| m.face(f),
        )
        .expect("tags")
    }

    #[test]
    fn unknown_scheme() {
        let m = cube(false);
        let e = Request::uniform("nope", 2).validate(&m).unwrap_err();
        assert!(matches!(e, Error::UnknownScheme { ref name, .. } if name == "nope"));
        assert!(e.to_string().contains("available: "), "{e}");
    }

    #[test]
    fn level_range() {
        let m = cube(false);
        for level in [0, MAX_LEVEL + 1] {
            let e = Request::uniform("pccm", level).validate(&m).unwrap_err();
            assert!(matches!(e, Error::Level { level: l } if l == level), "{e}");
        }
        assert!(Request::uniform("pccm", MAX_LEVEL).validate(&m).is_ok());
    }

    #[test]
    fn tags_only_for_stpn() {
        let m = cube(false);
        let t = tags(&m);
        let e = Request::uniform("pn", 2)
            .split_quads(true)
            .tagged(&t)
            .validate(&m)
            .unwrap_err();
        assert!(
            matches!(e, Error::TagsUnused { ref scheme } if scheme == "pn"),
            "{e}"
        );
        assert!(e.to_string().contains("only `stpn` reads them"));
        assert!(Request::uniform("stpn", 2)
            .split_quads(true)
            .tagged(&t)
            .validate(&m)
            .is_ok());
    }

    #[test]
    fn tags_do_not_combine_with_displacement() {
        let m = cube(true);
        let (t, d) = (tags(&m), displacement());
        let e = Request::uniform("stpn", 2)
            .split_quads(true)
            .tagged(&t)
            .displaced(&d)
            .validate(&m)
            .unwrap_err();
        assert!(matches!(e, Error::TagsWithDisplacement), "{e}");
    }

    #[test]
    fn fractional_partitioning_needs_the_hardware_tessellator() {
        let m = cube(false);
        let e = Request::adaptive("pccm", adaptive(Partitioning::FractionalOdd))
            .validate(&m)
            .unwrap_err();
        assert!(
            matches!(e, Error::Partitioning { backend: "cpu", .. }),
            "{e}"
        );
        assert!(e.to_string().contains("integer only"), "{e}");
        let r = Request::adaptive("pccm", adaptive(Partitioning::Integer));
        let v = r.validate(&m).expect("integer on the CPU");
        // Instanced: power-of-two clamp, factors drawn per quad edge (12).
        let a = v.adaptive().expect("adaptive");
        assert_eq!(a.max, 8.0);
        assert!(matches!(&a.metric, Metric::Buffer(f) if f.len() == 12));
    }

    #[cfg(feature = "vulkan")]
    #[test]
    fn fractional_partitioning_on_the_hardware_tessellator() {
        let m = cube(false);
        let mut a = adaptive(Partitioning::FractionalEven);
        a.max_factor = 6.5;
        let r = Request::adaptive("pccm", a).on(Backend::VulkanHlsl);
        let v = r.validate(&m).expect("fractional on hlsl");
        let a = v.adaptive().expect("adaptive");
        assert_eq!((a.partitioning, a.max), (Partitioning::FractionalEven, 6.5));
    }

    #[test]
    fn quad_scheme_refines_triangles_at_even_levels() {
        let m = mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
        let request = Request::uniform("pccm", 2);
        let v = request.validate(&m).expect("one step");
        let r = v.refined().expect("refined");
        assert_eq!((r.refinement.levels, r.leaf_level), (1, 1));
        assert_eq!(r.refinement.blocks.len(), 12);
        let e = Request::uniform("pccm", 3).validate(&m).unwrap_err();
        assert!(matches!(e, Error::Refine(_)), "{e}");
    }

    #[test]
    fn triangle_scheme_needs_triangles_or_split_quads() {
        let m = cube(false);
        let e = Request::uniform("pn", 2).validate(&m).unwrap_err();
        assert!(matches!(e, Error::Tess(TessError::TriMesh(_))), "{e}");
        assert!(e.to_string().contains("face 0"), "{e}");
        assert!(Request::uniform("pn", 2)
            .split_quads(true)
            .validate(&m)
            .is_ok());
    }

    #[test]
    fn regular_refuses_extraordinary_faces() {
        let m = cube(false);
        let e = Request::uniform("regular", 2).validate(&m).unwrap_err();
        assert!(
            matches!(e, Error::Tess(TessError::ExtraordinaryFace { face: 0, .. })),
            "{e}"
        );
    }

    #[test]
    fn displacement_needs_texcoords() {
        let (plain, d) = (cube(false), displacement());
        let e = Request::uniform("pccm", 2)
            .displaced(&d)
            .validate(&plain)
            .unwrap_err();
        assert!(
            matches!(
                e,
                Error::Tess(TessError::Displace(DisplaceError::MissingTexCoord {
                    face: 0,
                    corner: 0
                }))
            ),
            "{e}"
        );
        let uv = cube(true);
        assert!(Request::uniform("pccm", 2)
            .displaced(&d)
            .validate(&uv)
            .is_ok());
    }

    #[test]
    fn power_of_two_levels() {
        assert_eq!(power_of_two_level(0.5), 1);
        assert_eq!(power_of_two_level(12.0), 8);
        assert_eq!(power_of_two_level(64.0), 64);
        assert_eq!(power_of_two_level(1e9), MAX_LEVEL);
    }
}

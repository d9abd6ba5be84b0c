//! Adaptive evaluation on the instanced path: the checks both adaptive
//! paths make before any GPU work, the host-list path (levels classified on
//! the GPU, read back, bucket lists built on the host) and
//! [`GpuMesh::evaluate_adaptive`], which picks it or the GPU-driven buckets
//! (`buckets.rs`).

use crate::abi::{self, binding};
use crate::cpu;
use crate::gpu::upload::params_bytes;
use glam::{Mat4, Vec3};

use crate::gpu::readback::patch_runs;

use super::device::check;
use super::{GpuError, GpuMesh};

/// An adaptive run classified on the GPU ([`GpuMesh::classify_adaptive`]):
/// the levels read back and laid out per face, from which any window of
/// faces is evaluated ([`GpuMesh::evaluate_classified`]).
pub struct Classified {
    /// `abi::LEVELS_LEN` words per class-sorted patch (its edge levels,
    /// then its bucket).
    words: Vec<u32>,
    /// Bucket level per face.
    levels: Vec<u32>,
    /// `sides` edge levels per face.
    edge_levels: Vec<u32>,
    /// Where each face's grid starts in the whole result (`faces + 1`).
    offsets: Vec<usize>,
}

impl Classified {
    /// Where each face's grid starts in the whole result (`faces + 1`
    /// entries, the last the total).
    pub fn offsets(&self) -> &[usize] {
        &self.offsets
    }
}

impl<'g> GpuMesh<'g> {
    /// The checks both adaptive paths make before any GPU work — the mesh
    /// is of the scheme's domain (`Domain`) and the uploaded one
    /// (`MeshMismatch`) — and the edge inputs (factors, face edges, params).
    pub(crate) fn adaptive_inputs(
        &self,
        mesh: crate::cpu::adaptive::AdaptiveMesh<'_>,
        a: &crate::cpu::adaptive::Adaptive,
        max_level: u32,
    ) -> Result<crate::cpu::adaptive::EdgeInputs, GpuError> {
        crate::cpu::adaptive::check_mesh(self.scheme, &mesh, self.patch_faces.len())?;
        Ok(crate::cpu::adaptive::edge_inputs(mesh, a, max_level)?)
    }

    /// Per-face bucket levels, edge levels and sample offsets from the
    /// classify output (`patch_levels`: PATCH_LEVELS_WORDS per class-sorted patch, the
    /// edge levels then the bucket).
    pub(super) fn face_levels(&self, words: &[u32]) -> (Vec<u32>, Vec<u32>, Vec<usize>) {
        let (faces, sides) = (self.patch_faces.len(), self.scheme.sides as usize);
        let mut levels = vec![0u32; faces];
        let mut edge_levels = vec![0u32; sides * faces];
        for (p, &face) in self.patch_faces.iter().enumerate() {
            let (w, face) = (
                &words[abi::LEVELS_LEN * p..][..abi::LEVELS_LEN],
                face as usize,
            );
            levels[face] = w[abi::LEVELS_BUCKET];
            edge_levels[sides * face..sides * face + sides].copy_from_slice(&w[..sides]);
        }
        let mut offsets = Vec::with_capacity(faces + 1);
        let mut total = 0usize;
        for &l in &levels {
            offsets.push(total);
            total += (self.scheme.grid_len)(l) as usize;
        }
        offsets.push(total);
        (levels, edge_levels, offsets)
    }

    /// Adaptive tessellation on the instanced path (quad schemes on a
    /// [`Topology`](crate::mesh::topology::Topology), triangle schemes on the [`crate::mesh::trimesh::TriMesh`]
    /// uploaded with [`GpuMesh::new_tri`]), the same result as
    /// [`crate::cpu::adaptive::evaluate_cpu_adaptive`] bit for bit:
    ///
    /// 1. `adaptive_classify_main`, one dispatch per class: every patch's
    ///    four power-of-two edge levels (triangles: three, slot 3 is 1) (the metric of `a`, computed on the
    ///    GPU from the edge's end points or read from the explicit factors;
    ///    largest level `max_level`) and its bucket (the largest of the four)
    ///    into `patch_levels`;
    /// 2. a small readback of `patch_levels` (5 u32 per patch) from which the
    ///    host builds one entry list per (class, bucket) in `bucket_patches`
    ///    — not GPU-driven: no atomic bucket counters or indirect arguments;
    /// 3. `eval_adaptive_main`, one dispatch per (class, bucket) at the
    ///    bucket's level (split at the device limits), boundary samples
    ///    snapped onto the edges' own levels; read back in face order.
    ///
    /// A renderer draws step 3 with `eval_adaptive_vs` instead: one
    /// instanced draw of the level's grid per (class, bucket).
    ///
    /// Both entries evaluate through `eval_adaptive_displaced`: on a mesh
    /// uploaded with displacement ([`GpuMesh::new_displaced`],
    /// [`GpuMesh::new_tri_displaced`]) the result is displaced with
    /// ownership (measured: the same bits as
    /// [`crate::cpu::adaptive::evaluate_cpu_adaptive_displaced`] for pccm, pn
    /// and phong; gregory within 2.4e-8 × diagonal, its interior normal);
    /// otherwise (scale 0) it is the undisplaced tessellation bit for bit.
    ///
    /// This is the host-list path; [`GpuMesh::evaluate_adaptive`] runs
    /// [`GpuMesh::evaluate_adaptive_gpu_driven`] instead whenever its
    /// samples buffer (every patch at `max_level`) fits the binding limit.
    pub fn evaluate_adaptive_host_lists<'m>(
        &self,
        mesh: impl Into<crate::cpu::adaptive::AdaptiveMesh<'m>>,
        a: &crate::cpu::adaptive::Adaptive,
        max_level: u32,
    ) -> Result<crate::cpu::adaptive::AdaptiveTessellation, GpuError> {
        let classified = self.classify_adaptive(mesh, a, max_level)?;
        let mut t = self.evaluate_classified(&classified, 0..self.patch_faces.len())?;
        t.face_ids.clear();
        Ok(t)
    }

    /// Step 1 of the host-list path, for the whole mesh: the classify
    /// dispatches, then the levels read back (5 words a patch) and laid out
    /// per face. [`GpuMesh::evaluate_classified`] then evaluates any window
    /// of faces from it: the streamed form (`tessellate::Session::run_chunked`)
    /// classifies once and reads back one window's samples at a time.
    pub fn classify_adaptive<'m>(
        &self,
        mesh: impl Into<crate::cpu::adaptive::AdaptiveMesh<'m>>,
        a: &crate::cpu::adaptive::Adaptive,
        max_level: u32,
    ) -> Result<Classified, GpuError> {
        let inp = self.adaptive_inputs(mesh.into(), a, max_level)?;
        let dev = &self.gpu.device;
        let storage = |label, bytes: &[u8], extra| self.storage_init(label, bytes, extra);
        use crate::gpu::upload::{f32_bytes, u32_bytes};
        let patches = self.patch_faces.len() as u64;
        check(
            &self.gpu.info.name,
            &self.limits,
            "patch_levels",
            patches * abi::LEVELS_BYTES,
        )?;
        let face_edges = storage(
            "face_edges",
            &u32_bytes(&inp.face_edges),
            wgpu::BufferUsages::empty(),
        );
        let edge_factors = storage(
            "edge_factors",
            &f32_bytes(&inp.edge_factors),
            wgpu::BufferUsages::empty(),
        );
        let params_buf = storage(
            "adaptive",
            &f32_bytes(&inp.params),
            wgpu::BufferUsages::empty(),
        );
        let levels_buf = storage(
            "patch_levels",
            &vec![0u8; patches as usize * 20],
            wgpu::BufferUsages::COPY_SRC,
        );
        let extra = [
            (binding::FACE_EDGES, &face_edges),
            (binding::EDGE_FACTORS, &edge_factors),
            (binding::ADAPTIVE, &params_buf),
            (binding::PATCH_LEVELS, &levels_buf),
        ];
        let classify = self.compute_pipeline("adaptive_classify_main")?;

        // 1. classify, then read the levels back.
        let staging = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("patch_levels readback"),
            size: (patches * abi::LEVELS_BYTES).max(16),
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.gpu.scoped(|| {
            let chunk = self.chunk(1) as u32;
            let mut groups = Vec::new();
            for c in &self.classes {
                let mut k = 0;
                while k < c.count {
                    let count = chunk.min(c.count - k);
                    let p = self.params_buffer(&params_bytes(
                        Mat4::IDENTITY,
                        c.first + k,
                        count,
                        c.class,
                        c.cp_base + k * c.points,
                        max_level,
                        0,
                    ));
                    let layout = classify.get_bind_group_layout(0);
                    groups.push((
                        self.bind_group_with("adaptive_classify_main", &layout, &p, None, &extra),
                        count.div_ceil(abi::WORKGROUP_SIZE),
                    ));
                    k += count;
                }
            }
            let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("adaptive classify"),
            });
            {
                let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("adaptive classify"),
                    timestamp_writes: None,
                });
                pass.set_pipeline(&classify);
                for (group, wgs) in &groups {
                    pass.set_bind_group(0, group, &[]);
                    pass.dispatch_workgroups(*wgs, 1, 1);
                }
            }
            enc.copy_buffer_to_buffer(&levels_buf, 0, &staging, 0, patches * abi::LEVELS_BYTES);
            self.gpu.queue.submit([enc.finish()]);
        })?;
        let words = self.read_words(&staging)?;
        let (levels, edge_levels, offsets) = self.face_levels(&words);
        Ok(Classified {
            words,
            levels,
            edge_levels,
            offsets,
        })
    }

    /// Steps 2 and 3 of the host-list path for the faces `faces` (clamped
    /// to the mesh's) of a classified run: one entry list per (class,
    /// bucket) of just those faces' patches, one dispatch per list (split
    /// at the device limits), read back into a result holding just those
    /// faces (`face_ids` = the range, `edge_levels` of every face, as
    /// [`crate::cpu::adaptive::AdaptiveRun::evaluate`] gives them). Each
    /// sample is the whole run's, bit for bit.
    pub fn evaluate_classified(
        &self,
        classified: &Classified,
        faces: std::ops::Range<usize>,
    ) -> Result<crate::cpu::adaptive::AdaptiveTessellation, GpuError> {
        let dev = &self.gpu.device;
        let storage = |label, bytes: &[u8], extra| self.storage_init(label, bytes, extra);
        use crate::gpu::upload::u32_bytes;
        let eval = self.compute_pipeline("eval_adaptive_main")?;
        let Classified {
            words,
            levels,
            edge_levels,
            offsets,
        } = classified;
        let faces = cpu::clamp_window(faces, self.patch_faces.len());
        let base = offsets[faces.start];
        let total = offsets[faces.end] - base;

        // 2. one entry list per (class, bucket) of the window's patches
        // (each class's runs cut to the window, in patch order).
        let mut lists: std::collections::BTreeMap<(u32, u32), Vec<u32>> = Default::default();
        for (ci, run) in patch_runs(&self.patch_faces, &self.classes, faces.clone()) {
            let c = &self.classes[ci];
            for p in run {
                let k = p as u32 - c.first;
                let w = &words[abi::LEVELS_LEN * p as usize..][..abi::LEVELS_LEN];
                lists
                    .entry((c.class, w[abi::LEVELS_BUCKET]))
                    .or_default()
                    .extend([p as u32, c.cp_base + k * c.points, w[0], w[1], w[2], w[3]]);
            }
        }
        let all: Vec<u32> = lists.values().flatten().copied().collect();
        check(
            &self.gpu.info.name,
            &self.limits,
            "bucket_patches",
            all.len() as u64 * abi::WORD_BYTES,
        )?;
        let bucket_buf = storage(
            "bucket_patches",
            &u32_bytes(&all),
            wgpu::BufferUsages::empty(),
        );

        // 3. one dispatch per (class, bucket), split at the limits.
        let (mut positions, mut normals) = (Vec::new(), Vec::new());
        cpu::reserve_samples(&mut positions, &mut normals, total)?;
        positions.resize(total, Vec3::ZERO);
        normals.resize(total, Vec3::ZERO);
        let mut start = 0u32;
        for (&(class, level), list) in &lists {
            let n = (list.len() / abi::ENTRY_LEN) as u32;
            let spp = (self.scheme.grid_len)(level) as u64;
            if spp * abi::SAMPLE_BYTES > self.limits.max_storage_buffer_binding_size {
                return Err(GpuError::BufferTooLarge {
                    what: "samples of one patch",
                    needed: spp * abi::SAMPLE_BYTES,
                    max: self.limits.max_storage_buffer_binding_size,
                    adapter: self.gpu.info.name.clone(),
                });
            }
            let by_binding =
                (self.limits.max_storage_buffer_binding_size / (spp * abi::SAMPLE_BYTES)).max(1);
            let chunk = self.chunk(spp).min(by_binding) as u32;
            let mut k = 0;
            while k < n {
                let count = chunk.min(n - k);
                let bytes = count as u64 * spp * abi::SAMPLE_BYTES;
                let (samples, staging) = self.sample_buffers(bytes);
                self.gpu.scoped(|| {
                    let p = self.params_buffer(&params_bytes(
                        Mat4::IDENTITY,
                        start + k,
                        count,
                        class,
                        0,
                        level,
                        0,
                    ));
                    let layout = eval.get_bind_group_layout(0);
                    let group = self.bind_group_with(
                        "eval_adaptive_main",
                        &layout,
                        &p,
                        Some(&samples),
                        &[(binding::BUCKET_PATCHES, &bucket_buf)],
                    );
                    let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("eval adaptive"),
                    });
                    {
                        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                            label: Some("eval adaptive"),
                            timestamp_writes: None,
                        });
                        pass.set_pipeline(&eval);
                        pass.set_bind_group(0, &group, &[]);
                        pass.dispatch_workgroups(
                            ((count as u64 * spp).div_ceil(abi::WORKGROUP)) as u32,
                            1,
                            1,
                        );
                    }
                    enc.copy_buffer_to_buffer(&samples, 0, &staging, 0, bytes);
                    self.gpu.queue.submit([enc.finish()]);
                })?;
                let floats = self.read(&staging)?;
                for (i, s) in floats.chunks_exact(abi::SAMPLE_LEN).enumerate() {
                    let entry = (k as u64 + i as u64 / spp) as usize;
                    let face = self.patch_faces[list[abi::ENTRY_LEN * entry] as usize] as usize;
                    let at = offsets[face] - base + (i as u64 % spp) as usize;
                    positions[at] = Vec3::new(s[0], s[1], s[2]);
                    normals[at] = Vec3::new(s[3], s[4], s[5]);
                }
                k += count;
            }
            start += n;
        }
        Ok(crate::cpu::adaptive::AdaptiveTessellation {
            sides: self.scheme.sides,
            levels: levels[faces.clone()].to_vec(),
            edge_levels: edge_levels.clone(),
            offsets: offsets[faces.start..=faces.end]
                .iter()
                .map(|&o| o - base)
                .collect(),
            positions,
            normals,
            face_ids: faces.map(|f| f as u32).collect(),
        })
    }

    /// Adaptive tessellation on the instanced path (quad schemes on a
    /// [`Topology`](crate::mesh::topology::Topology), triangle schemes on the [`crate::mesh::trimesh::TriMesh`]
    /// uploaded with [`GpuMesh::new_tri`]), the same result as
    /// [`crate::cpu::adaptive::evaluate_cpu_adaptive`] (or `_displaced`, on a
    /// mesh uploaded with displacement): GPU-driven buckets
    /// ([`GpuMesh::evaluate_adaptive_gpu_driven`], no readback before the
    /// evaluation) when every patch's samples at `max_level` fit one
    /// storage binding, otherwise the host-list path
    /// ([`GpuMesh::evaluate_adaptive_host_lists`], which splits its
    /// dispatches at the limits). Both give the same bits.
    pub fn evaluate_adaptive<'m>(
        &self,
        mesh: impl Into<crate::cpu::adaptive::AdaptiveMesh<'m>>,
        a: &crate::cpu::adaptive::Adaptive,
        max_level: u32,
    ) -> Result<crate::cpu::adaptive::AdaptiveTessellation, GpuError> {
        let bytes = self.patch_faces.len() as u64
            * (self.scheme.grid_len)(max_level) as u64
            * abi::SAMPLE_BYTES;
        if max_level.is_power_of_two()
            && max_level <= cpu::MAX_LEVEL
            && bytes <= self.limits.max_storage_buffer_binding_size
            && self.chunk_rows() <= self.limits.max_workgroups_per_dimension as u64
        {
            self.evaluate_adaptive_gpu_driven(mesh, a, max_level)
        } else {
            self.evaluate_adaptive_host_lists(mesh, a, max_level)
        }
    }
}

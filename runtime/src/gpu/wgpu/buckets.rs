//! The GPU-driven adaptive buckets: per-patch levels, bucket lists and
//! indirect dispatch and draw arguments built on the GPU, so nothing is read
//! back before the evaluation; the buffers ([`Buckets`]) and phases are
//! shared with the instanced adaptive render.

use crate::abi::{self, binding};
use crate::gpu::upload::params_bytes;
use glam::{Mat4, Vec3};

use super::device::check;
use super::{GpuError, GpuMesh};

/// Bucket slots per class range of the GPU-driven adaptive buffers (slot
/// `BUCKET_SLOTS·r + j`: class range r, bucket `2^j`; from the ABI).
pub(crate) const SLOTS: u32 = abi::BUCKET_SLOTS;

/// Patches per chunk of the GPU-driven bucket compaction (one workgroup
/// each in `adaptive_count_main` / `adaptive_scatter_main`; from the ABI).
pub(crate) const CHUNK: u32 = abi::BUCKET_CHUNK;

/// How one compute run of a phase is dispatched: direct with x workgroups,
/// or indirect from the byte offset of its slot's arguments.
pub(crate) enum Run {
    Direct(u32),
    Indirect(u64),
}

/// The buffers of one GPU-driven adaptive run (see
/// [`GpuMesh::evaluate_adaptive_gpu_driven`]).
pub(crate) struct Buckets {
    face_edges: wgpu::Buffer,
    edge_factors: wgpu::Buffer,
    params: wgpu::Buffer,
    levels: wgpu::Buffer,
    list: wgpu::Buffer,
    dispatch: wgpu::Buffer,
    pub(crate) draw: wgpu::Buffer,
    chunks: wgpu::Buffer,
    pub(crate) slots: u32,
    list_words: u64,
}

impl Buckets {
    /// Rewrite the metric's inputs in place: the `adaptive` parameters and
    /// (explicit metrics) the factors, which must fit the buffer the
    /// buckets were made with. Every other buffer is rewritten whole by
    /// the next run of the phases (assignments, no atomics), so the
    /// buckets can run again every frame.
    pub(crate) fn write_inputs(&self, queue: &wgpu::Queue, params: &[f32], factors: &[f32]) {
        use crate::gpu::upload::f32_bytes;
        queue.write_buffer(&self.params, 0, &f32_bytes(params));
        if !factors.is_empty() {
            queue.write_buffer(&self.edge_factors, 0, &f32_bytes(factors));
        }
    }

    /// The per-call bindings: the edge inputs, the levels, the lists
    /// (also as `bucket_patches`, what the evaluation and the draws read)
    /// and the indirect arguments.
    pub(crate) fn bindings(&self) -> [(u32, &wgpu::Buffer); 9] {
        [
            (binding::FACE_EDGES, &self.face_edges),
            (binding::EDGE_FACTORS, &self.edge_factors),
            (binding::ADAPTIVE, &self.params),
            (binding::PATCH_LEVELS, &self.levels),
            (binding::BUCKET_LIST, &self.list),
            (binding::BUCKET_DISPATCH, &self.dispatch),
            (binding::BUCKET_DRAW, &self.draw),
            (binding::BUCKET_PATCHES, &self.list),
            (binding::BUCKET_CHUNKS, &self.chunks),
        ]
    }
}

impl<'g> GpuMesh<'g> {
    /// [`GpuMesh::evaluate_adaptive_host_lists`] with the buckets built on the GPU:
    /// nothing is read back before the evaluation.
    ///
    /// 1. `adaptive_classify_main` as there;
    /// 2. per class range r, `adaptive_count_main`: a workgroup per chunk
    ///    of [`abi::BUCKET_CHUNK`] patches counts the chunk's patches of each bucket
    ///    slot `16r + j` (bucket `2^j`) into `bucket_chunks`;
    /// 3. `adaptive_plan_main` (one workgroup): each chunk's offset within
    ///    each slot (a scan over the chunks per slot), each slot's count,
    ///    first entry and first sample (prefix sums) and its
    ///    `dispatch_workgroups_indirect` arguments (y = ⌈workgroups / 32768⌉
    ///    rows of x = ⌈workgroups / y⌉, so fewer than y are idle);
    /// 4. per class range, `adaptive_scatter_main`: a workgroup per chunk
    ///    writes every patch at its slot's first entry plus its chunk's
    ///    offset plus its rank in the chunk — patch order, no atomics, so the lists
    ///    are the host-built ones;
    /// 5. one `dispatch_workgroups_indirect` of `eval_adaptive_indirect_main`
    ///    per slot up to `max_level` (empty slots dispatch nothing).
    ///
    /// Then one readback of `patch_levels`, the lists and the samples,
    /// reassembled per face: the same [`crate::cpu::adaptive::AdaptiveTessellation`]
    /// as [`GpuMesh::evaluate_adaptive_host_lists`], bit for bit. The samples buffer
    /// is sized for every patch at `max_level` (the host does not know the
    /// buckets before the evaluation): `BufferTooLarge` beyond the binding
    /// limit, `TooManyChunks` beyond 256 × max_workgroups_per_dimension
    /// patches.
    pub fn evaluate_adaptive_gpu_driven<'m>(
        &self,
        mesh: impl Into<crate::cpu::adaptive::AdaptiveMesh<'m>>,
        a: &crate::cpu::adaptive::Adaptive,
        max_level: u32,
    ) -> Result<crate::cpu::adaptive::AdaptiveTessellation, GpuError> {
        let inp = self.adaptive_inputs(mesh.into(), a, max_level)?;
        let faces = self.patch_faces.len();
        let dev = &self.gpu.device;
        let b = self.bucket_buffers(&inp)?;
        let slots = b.slots;
        let patches = faces as u64;
        let max_spp = (self.scheme.grid_len)(max_level) as u64;
        let sample_bytes = (patches * max_spp * abi::SAMPLE_BYTES).max(abi::SAMPLE_BYTES);
        check(
            &self.gpu.info.name,
            &self.limits,
            "samples (every patch at the largest level)",
            sample_bytes,
        )?;
        let mut kept = self
            .driven_samples
            .lock()
            .map_err(|_| GpuError::Readback("samples buffer lock poisoned".into()))?;
        if kept.as_ref().is_some_and(|b| b.size() < sample_bytes) {
            *kept = None;
        }
        let samples: &wgpu::Buffer = kept.get_or_insert_with(|| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some("samples (GPU-driven adaptive)"),
                size: sample_bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        });
        let staging = |label: &'static str, size: u64| {
            dev.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.max(16),
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let levels_read = staging("patch_levels readback", patches * abi::LEVELS_BYTES);
        let list_read = staging("bucket_list readback", b.list_words * abi::WORD_BYTES);
        let mut phases = self.bucket_phases(max_level, slots, false);
        let mut evals = Vec::new();
        for (slot, class, level) in self.bucket_slots(max_level) {
            evals.push((
                self.slot_params(Mat4::IDENTITY, slots, class, level, slot, 0),
                Run::Indirect(12 * slot as u64),
            ));
        }
        phases.push(("eval_adaptive_indirect_main", evals));
        self.gpu.scoped(|| -> Result<(), GpuError> {
            let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("adaptive, GPU-driven"),
            });
            self.encode_phases(&mut enc, &phases, &b, Some(samples))?;
            enc.copy_buffer_to_buffer(&b.levels, 0, &levels_read, 0, patches * abi::LEVELS_BYTES);
            enc.copy_buffer_to_buffer(&b.list, 0, &list_read, 0, b.list_words * abi::WORD_BYTES);
            self.gpu.queue.submit([enc.finish()]);
            Ok(())
        })??;
        let lv = self.read_words(&levels_read)?;
        let list = self.read_words(&list_read)?;
        // After the evaluation, the headers say how many samples were
        // written (the end of the furthest slot: first sample + count ·
        // samples per patch): read back only those, not the buffer sized
        // for every patch at `max_level`.
        let written: u64 = (0..slots as usize)
            .map(|b| {
                let spp = (self.scheme.grid_len)(1 << (b as u32 % SLOTS)) as u64;
                list[abi::HEADER_LEN * b + 2] as u64 + list[abi::HEADER_LEN * b] as u64 * spp
            })
            .max()
            .unwrap_or(0)
            .min(patches * max_spp);
        let samples_read = staging("samples readback", written * abi::SAMPLE_BYTES);
        self.gpu.scoped(|| {
            let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("adaptive samples readback"),
            });
            enc.copy_buffer_to_buffer(samples, 0, &samples_read, 0, written * abi::SAMPLE_BYTES);
            self.gpu.queue.submit([enc.finish()]);
        })?;
        let floats = self.read(&samples_read)?;
        let (levels, edge_levels, offsets) = self.face_levels(&lv);
        let total = offsets[faces];
        let mut positions = vec![Vec3::ZERO; total];
        let mut normals = vec![Vec3::ZERO; total];
        for b in 0..slots as usize {
            let (n, first, sample) = (
                list[abi::HEADER_LEN * b] as usize,
                list[abi::HEADER_LEN * b + 1] as usize,
                list[abi::HEADER_LEN * b + 2] as usize,
            );
            let spp = (self.scheme.grid_len)(1 << (b as u32 % SLOTS)) as usize;
            for m in 0..n {
                let e = abi::HEADER_LEN * slots as usize + abi::ENTRY_LEN * (first + m);
                let face = self.patch_faces[list[e] as usize] as usize;
                for s in 0..spp {
                    let f = &floats[abi::SAMPLE_LEN * (sample + m * spp + s)..][..abi::SAMPLE_LEN];
                    positions[offsets[face] + s] = Vec3::new(f[0], f[1], f[2]);
                    normals[offsets[face] + s] = Vec3::new(f[3], f[4], f[5]);
                }
            }
        }
        Ok(crate::cpu::adaptive::AdaptiveTessellation {
            sides: self.scheme.sides,
            levels,
            edge_levels,
            offsets,
            positions,
            normals,
            face_ids: Vec::new(),
        })
    }

    /// The buffers of the GPU-driven buckets for the edge inputs `inp`
    /// (`patch_levels`, `bucket_list` with its header of 4 u32 per slot,
    /// the indirect dispatch and draw arguments), checked against the
    /// binding limit.
    pub(crate) fn bucket_buffers(
        &self,
        inp: &crate::cpu::adaptive::EdgeInputs,
    ) -> Result<Buckets, GpuError> {
        use crate::gpu::upload::{f32_bytes, u32_bytes};
        let storage = |label, bytes: &[u8], extra| self.storage_init(label, bytes, extra);
        let patches = self.patch_faces.len() as u64;
        let slots = SLOTS * self.classes.len() as u32;
        let list_words = abi::BUCKET_HEADER_WORDS as u64 * slots as u64
            + abi::BUCKET_ENTRY_WORDS as u64 * patches;
        check(
            &self.gpu.info.name,
            &self.limits,
            "patch_levels",
            patches * abi::LEVELS_BYTES,
        )?;
        check(
            &self.gpu.info.name,
            &self.limits,
            "bucket_list",
            list_words * abi::WORD_BYTES,
        )?;
        let chunk_rows = self.chunk_rows();
        if chunk_rows > self.limits.max_workgroups_per_dimension as u64 {
            return Err(GpuError::TooManyChunks {
                patches,
                chunks: chunk_rows,
                max: self.limits.max_workgroups_per_dimension,
                adapter: self.gpu.info.name.clone(),
            });
        }
        let chunk_words = 2 * chunk_rows * slots as u64;
        check(
            &self.gpu.info.name,
            &self.limits,
            "bucket_chunks",
            chunk_words * abi::WORD_BYTES,
        )?;
        let zeros = |words: u64| vec![0u8; (words * abi::WORD_BYTES) as usize];
        Ok(Buckets {
            face_edges: storage(
                "face_edges",
                &u32_bytes(&inp.face_edges),
                wgpu::BufferUsages::empty(),
            ),
            edge_factors: storage(
                "edge_factors",
                &f32_bytes(&inp.edge_factors),
                wgpu::BufferUsages::empty(),
            ),
            params: storage(
                "adaptive",
                &f32_bytes(&inp.params),
                wgpu::BufferUsages::empty(),
            ),
            levels: storage(
                "patch_levels",
                &zeros(abi::PATCH_LEVELS_WORDS as u64 * patches),
                wgpu::BufferUsages::COPY_SRC,
            ),
            list: storage(
                "bucket_list",
                &zeros(list_words),
                wgpu::BufferUsages::COPY_SRC,
            ),
            dispatch: storage(
                "bucket_dispatch",
                &zeros(abi::BUCKET_DISPATCH_WORDS as u64 * slots as u64),
                wgpu::BufferUsages::INDIRECT,
            ),
            draw: storage(
                "bucket_draw",
                &zeros(abi::BUCKET_DRAW_WORDS as u64 * slots as u64),
                wgpu::BufferUsages::INDIRECT,
            ),
            chunks: storage(
                "bucket_chunks",
                &zeros(chunk_words),
                wgpu::BufferUsages::empty(),
            ),
            slots,
            list_words,
        })
    }

    /// Chunks of [`CHUNK`] patches the bucket compaction runs over (one
    /// row of `bucket_chunks` each; at most max_workgroups_per_dimension,
    /// as `bucket_buffers` checks).
    pub(super) fn chunk_rows(&self) -> u64 {
        (self.patch_faces.len() as u64).div_ceil(CHUNK as u64)
    }

    /// Every bucket slot up to `max_level`: `(slot 16r + j, class of range
    /// r, level 2^j)`.
    pub(crate) fn bucket_slots(&self, max_level: u32) -> Vec<(u32, u32, u32)> {
        let mut out = Vec::new();
        for (r, c) in self.classes.iter().enumerate() {
            let mut j = 0;
            while (1u32 << j) <= max_level && j < SLOTS {
                out.push((SLOTS * r as u32 + j, c.class, 1 << j));
                j += 1;
            }
        }
        out
    }

    /// The Params of slot `slot`'s evaluation or draw: entries after the
    /// header of `slots` slots (`first`), the slot in `out_base`.
    pub(crate) fn slot_params(
        &self,
        view_proj: Mat4,
        slots: u32,
        class: u32,
        level: u32,
        slot: u32,
        flags: u32,
    ) -> wgpu::Buffer {
        self.params(view_proj, slots, 0, class, 0, level, slot, flags)
    }

    /// Steps 1–4 of the GPU-driven buckets (classify, count, plan, scatter)
    /// as `(entry, [(params, run)])`.
    pub(crate) fn bucket_phases(
        &self,
        max_level: u32,
        slots: u32,
        emitting_only: bool,
    ) -> Vec<(&'static str, Vec<(wgpu::Buffer, Run)>)> {
        let prm = |first, count, class, cp_base, level, out_base| {
            self.params_buffer(&params_bytes(
                Mat4::IDENTITY,
                first,
                count,
                class,
                cp_base,
                level,
                out_base,
            ))
        };
        let mut phases = Vec::new();
        let chunk = self.chunk(1) as u32;
        let mut classify = Vec::new();
        for c in &self.classes {
            let mut k = 0;
            while k < c.count {
                let count = chunk.min(c.count - k);
                let p = prm(
                    c.first + k,
                    count,
                    c.class,
                    c.cp_base + k * c.points,
                    max_level,
                    0,
                );
                classify.push((p, Run::Direct(count.div_ceil(abi::WORKGROUP_SIZE))));
                k += count;
            }
        }
        phases.push(("adaptive_classify_main", classify));
        // The count and scatter passes: per class range, a workgroup per
        // chunk of CHUNK patches that holds one of the range's patches.
        // With `emitting_only` (drawing) a range buckets only the patches
        // that emit, so holes are classified (their edges' levels are
        // their neighbours') but never drawn.
        let per_range = || {
            self.classes
                .iter()
                .enumerate()
                .map(|(r, c)| (r, c, if emitting_only { c.emitting } else { c.count }))
                .filter(|&(_, _, count)| count > 0)
                .map(|(r, c, count)| {
                    let p = prm(c.first, count, c.class, c.cp_base, slots, SLOTS * r as u32);
                    let chunks = (c.first + count - 1) / CHUNK - c.first / CHUNK + 1;
                    (p, Run::Direct(chunks))
                })
                .collect::<Vec<_>>()
        };
        phases.push(("adaptive_count_main", per_range()));
        phases.push((
            "adaptive_plan_main",
            vec![(
                prm(self.chunk_rows() as u32, slots, 0, 0, 0, 0),
                Run::Direct(1),
            )],
        ));
        phases.push(("adaptive_scatter_main", per_range()));
        phases
    }

    /// Record compute `phases` into `enc`, each run with the bucket
    /// buffers `b` bound (and `samples`).
    pub(crate) fn encode_phases(
        &self,
        enc: &mut wgpu::CommandEncoder,
        phases: &[(&'static str, Vec<(wgpu::Buffer, Run)>)],
        b: &Buckets,
        samples: Option<&wgpu::Buffer>,
    ) -> Result<(), GpuError> {
        let extra = b.bindings();
        for (entry, runs) in phases {
            let pipeline = self.compute_pipeline(entry)?;
            let layout = pipeline.get_bind_group_layout(0);
            let groups: Vec<wgpu::BindGroup> = runs
                .iter()
                .map(|(p, _)| self.bind_group_with(entry, &layout, p, samples, &extra))
                .collect();
            let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(entry),
                timestamp_writes: None,
            });
            pass.set_pipeline(&pipeline);
            for ((_, run), group) in runs.iter().zip(&groups) {
                pass.set_bind_group(0, group, &[]);
                match run {
                    Run::Direct(x) => pass.dispatch_workgroups(*x, 1, 1),
                    Run::Indirect(at) => pass.dispatch_workgroups_indirect(&b.dispatch, *at),
                }
            }
        }
        Ok(())
    }
}

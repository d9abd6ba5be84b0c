//! What every compute pass of a [`GpuMesh`] shares: the Params block,
//! storage buffers, the compute pipelines (built once per entry and kept),
//! bind groups laid out from an entry's ABI bindings, dispatch chunking at
//! the device limits, and reading staging buffers back.

use crate::abi::{self, binding, PARAMS_SIZE};
use crate::gpu::upload::params_bytes;
use glam::Mat4;
use std::collections::HashMap;

use super::{Gpu, GpuError, GpuMesh};

impl<'g> GpuMesh<'g> {
    pub(crate) fn gpu(&self) -> &Gpu {
        self.gpu
    }

    /// A Params uniform buffer.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn params(
        &self,
        view_proj: Mat4,
        first: u32,
        count: u32,
        class: u32,
        cp_base: u32,
        level: u32,
        out_base: u32,
        flags: u32,
    ) -> wgpu::Buffer {
        let mut bytes = params_bytes(view_proj, first, count, class, cp_base, level, out_base);
        crate::gpu::upload::set_params_flags(&mut bytes, flags);
        self.params_buffer(&bytes)
    }

    /// A storage buffer holding `bytes` (at least 16 bytes), with `extra`
    /// usages on top of STORAGE | COPY_DST.
    /// A `samples` storage buffer of `bytes` for one evaluation dispatch and
    /// the mappable buffer it is copied into for readback.
    pub(super) fn sample_buffers(&self, bytes: u64) -> (wgpu::Buffer, wgpu::Buffer) {
        let dev = &self.gpu.device;
        let samples = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("samples"),
            size: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let staging = dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some("samples readback"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        (samples, staging)
    }

    pub(super) fn storage_init(
        &self,
        label: &'static str,
        bytes: &[u8],
        extra: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        let buf = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: (bytes.len() as u64).max(16),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | extra,
            mapped_at_creation: false,
        });
        self.gpu.queue.write_buffer(&buf, 0, bytes);
        buf
    }

    /// The compute pipeline of one entry point of the scheme's module
    /// (layout derived from the shader), built once per mesh.
    pub(super) fn compute_pipeline(&self, entry: &str) -> Result<wgpu::ComputePipeline, GpuError> {
        let cached = |m: &HashMap<String, wgpu::ComputePipeline>| m.get(entry).cloned();
        if let Some(p) = self.pipelines.lock().ok().as_deref().and_then(cached) {
            return Ok(p);
        }
        let p = self.gpu.scoped(|| {
            self.gpu.count_pipeline();
            self.gpu
                .device
                .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: None,
                    module: &self.module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
        })?;
        if let Ok(mut m) = self.pipelines.lock() {
            m.insert(entry.to_string(), p.clone());
        }
        Ok(p)
    }

    /// Little-endian u32 words of a MAP_READ buffer.
    pub(super) fn read_words(&self, staging: &wgpu::Buffer) -> Result<Vec<u32>, GpuError> {
        Ok(self
            .read_bytes(staging)?
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect())
    }

    pub(super) fn params_buffer(&self, bytes: &[u8]) -> wgpu::Buffer {
        let buf = self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: PARAMS_SIZE,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.gpu.queue.write_buffer(&buf, 0, bytes);
        buf
    }

    /// Bind group for `entry` with exactly the bindings it uses.
    pub(crate) fn bind_group(
        &self,
        entry: &str,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
        samples: Option<&wgpu::Buffer>,
    ) -> wgpu::BindGroup {
        self.bind_group_with(entry, layout, params, samples, &[])
    }

    /// [`GpuMesh::bind_group`] with per-call buffers (`extra`, by binding)
    /// taking precedence over the mesh's own.
    pub(crate) fn bind_group_with(
        &self,
        entry: &str,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
        samples: Option<&wgpu::Buffer>,
        extra: &[(u32, &wgpu::Buffer)],
    ) -> wgpu::BindGroup {
        let used = self.bindings.get(entry).cloned().unwrap_or_default();
        let mut entries = Vec::new();
        for b in used {
            if let Some((_, buf)) = extra.iter().find(|(k, _)| *k == b) {
                entries.push(wgpu::BindGroupEntry {
                    binding: b,
                    resource: buf.as_entire_binding(),
                });
                continue;
            }
            let resource = match b {
                binding::STENCIL_TABLE => wgpu::BindingResource::TextureView(&self.table_view),
                binding::DISPLACE_MAP => wgpu::BindingResource::TextureView(&self.displace_view),
                binding::PARAMS => params.as_entire_binding(),
                binding::SAMPLES => match samples {
                    Some(s) => s.as_entire_binding(),
                    None => continue,
                },
                // The refinement stage writes the buffer the vertex stage
                // reads as `positions` (abi: `refined_positions`).
                binding::REFINED_POSITIONS => match self.buffers.get(&binding::POSITIONS) {
                    Some(buf) => buf.as_entire_binding(),
                    None => continue,
                },
                other => match self.buffers.get(&other) {
                    Some(buf) => buf.as_entire_binding(),
                    None => continue,
                },
            };
            entries.push(wgpu::BindGroupEntry {
                binding: b,
                resource,
            });
        }
        self.gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(entry),
                layout,
                entries: &entries,
            })
    }

    /// Items per dispatch so that `items · per_item / WORKGROUP_SIZE` workgroups fit the limit.
    pub(super) fn chunk(&self, per_item: u64) -> u64 {
        let max_threads = self.limits.max_workgroups_per_dimension as u64 * abi::WORKGROUP;
        (max_threads / per_item.max(1)).max(1)
    }

    /// Map a MAP_READ buffer and decode its floats (straight from the
    /// mapping: one host copy of a readback, not two).
    pub(super) fn read(&self, staging: &wgpu::Buffer) -> Result<Vec<f32>, GpuError> {
        self.with_mapped(staging, |bytes| {
            bytes
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect()
        })
    }

    /// Map a MAP_READ buffer and copy its bytes out.
    pub fn read_bytes(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
        self.with_mapped(staging, |bytes| bytes.to_vec())
    }

    /// Map a MAP_READ buffer, hand its bytes to `f`, unmap.
    fn with_mapped<T>(
        &self,
        staging: &wgpu::Buffer,
        f: impl FnOnce(&[u8]) -> T,
    ) -> Result<T, GpuError> {
        let gpu = self.gpu;
        gpu.check_lost()?;
        let failed = |e: String| gpu.or_lost(GpuError::Readback(e));
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        gpu.device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map_err(|e| failed(e.to_string()))?;
        rx.recv()
            .map_err(|e| failed(e.to_string()))?
            .map_err(|e| failed(e.to_string()))?;
        let data = staging
            .get_mapped_range(..)
            .map_err(|e| failed(e.to_string()))?;
        let out = f(&data);
        drop(data);
        staging.unmap();
        Ok(out)
    }

    /// The shader module (for render pipelines).
    pub fn module(&self) -> &wgpu::ShaderModule {
        &self.module
    }
}

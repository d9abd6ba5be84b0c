//! The wgpu device: adapter, device and queue ([`Gpu`]), the limits this
//! crate plans its dispatches with ([`Limits`]), the errors of the wgpu path
//! ([`GpuError`]), the check of one buffer or texture against those limits,
//! and each WGSL entry's bindings as the ABI declares them.

use crate::cpu;
use crate::gpu::upload::UploadError;
use std::collections::HashMap;

use super::CHUNK;

/// Errors of the GPU path.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found (on CI install Mesa's lavapipe: apt-get install mesa-vulkan-drivers)"
    )]
    NoAdapter,
    #[error("no adapter matches TESSGEN_ADAPTER={0:?}")]
    AdapterNotFound(String),
    #[error("requesting the device failed: {0}")]
    Device(String),
    #[error("no WGSL for scheme `{0}` in this build")]
    NoShader(String),
    #[error("generated WGSL does not parse/validate: {0}")]
    Shader(String),
    #[error("the displacement map ({width}x{height}) exceeds max_texture_dimension_2d = {max}")]
    MapTooLarge { width: u32, height: u32, max: u32 },
    #[error("the stencil table ({width}x{height}) exceeds max_texture_dimension_2d = {max}")]
    TableTooLarge { width: u32, height: u32, max: u32 },
    #[error("{what} needs {needed} bytes in one binding, more than max_storage_buffer_binding_size = {max}")]
    BufferTooLarge {
        what: &'static str,
        needed: u64,
        max: u64,
    },
    #[error("{patches} patches need {chunks} workgroups of {CHUNK} in one dispatch of the GPU-driven buckets, more than max_workgroups_per_dimension = {max}")]
    TooManyChunks { patches: u64, chunks: u64, max: u32 },
    #[error("wgpu reported an error: {0}")]
    Wgpu(String),
    #[error("image: {0}")]
    Image(String),
    #[error("readback failed: {0}")]
    Readback(String),
    #[error(transparent)]
    Tess(#[from] cpu::TessError),
    #[error("positions: expected {expected}, got {got}")]
    PositionCount { expected: usize, got: usize },
    /// The upload was refused for another reason (a refinement stencil
    /// table that does not fit the mesh).
    #[error(transparent)]
    Upload(UploadError),
    #[error(transparent)]
    Adaptive(#[from] crate::cpu::adaptive::AdaptiveError),
}

impl From<UploadError> for GpuError {
    fn from(e: UploadError) -> Self {
        match e {
            UploadError::Tess(e) => GpuError::Tess(e),
            UploadError::PositionCount { expected, got } => {
                GpuError::PositionCount { expected, got }
            }
            e @ UploadError::Refinement { .. } => GpuError::Upload(e),
        }
    }
}

/// The limits this crate plans its dispatches with. Defaults come from the
/// device; tests force them small to exercise splitting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    pub max_workgroups_per_dimension: u32,
    pub max_texture_dimension_2d: u32,
    pub max_storage_buffer_binding_size: u64,
}

/// A device and queue.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: Limits,
}

impl Gpu {
    /// Pick an adapter: `TESSGEN_ADAPTER` (substring of the adapter name) if
    /// set, else the first high-performance adapter, software ones included
    /// (Mesa's lavapipe in CI).
    pub fn new() -> Result<Gpu, GpuError> {
        pollster::block_on(Self::new_async())
    }

    async fn new_async() -> Result<Gpu, GpuError> {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        if std::env::var_os("WGPU_BACKEND").is_none() {
            desc.backends = wgpu::Backends::PRIMARY;
        }
        let instance = wgpu::Instance::new(desc);
        let adapter = match std::env::var("TESSGEN_ADAPTER") {
            Ok(want) => {
                let all = instance.enumerate_adapters(wgpu::Backends::all()).await;
                all.into_iter()
                    .find(|a| {
                        a.get_info()
                            .name
                            .to_lowercase()
                            .contains(&want.to_lowercase())
                    })
                    .ok_or(GpuError::AdapterNotFound(want))?
            }
            Err(_) => instance
                .request_adapter(&wgpu::RequestAdapterOptions {
                    power_preference: wgpu::PowerPreference::HighPerformance,
                    force_fallback_adapter: false,
                    compatible_surface: None,
                    ..Default::default()
                })
                .await
                .map_err(|_| GpuError::NoAdapter)?,
        };
        let info = adapter.get_info();
        let alimits = adapter.limits();
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("tessgen"),
                required_features: wgpu::Features::empty(),
                required_limits: alimits.clone(),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::Device(e.to_string()))?;
        let limits = Limits {
            max_workgroups_per_dimension: alimits.max_compute_workgroups_per_dimension,
            max_texture_dimension_2d: alimits.max_texture_dimension_2d,
            max_storage_buffer_binding_size: alimits.max_storage_buffer_binding_size as u64,
        };
        Ok(Gpu {
            device,
            queue,
            info,
            limits,
        })
    }

    /// Run `f` and turn any wgpu validation error it caused into a `GpuError`.
    pub(crate) fn scoped<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(GpuError::Wgpu(e.to_string())),
            None => Ok(out),
        }
    }
}

/// Which bindings each entry point of `scheme`'s WGSL module uses, from the
/// ABI declared once in codegen (`abi::WGSL_ENTRIES`, `patch_main`'s per
/// scheme in `abi::PATCH_MAIN`), so bind groups match the pipelines'
/// automatic layouts exactly. No shader reflection at run time: the test
/// `validate_wgsl::abi_entry_bindings_match_naga` proves the lists equal what
/// naga reads from every emitted module.
pub(super) fn entry_bindings(scheme: &str) -> Result<HashMap<String, Vec<u32>>, GpuError> {
    let mut out = HashMap::new();
    for (name, _, bindings) in crate::abi::WGSL_ENTRIES {
        let list = if *name == "patch_main" {
            crate::abi::PATCH_MAIN
                .iter()
                .find(|(s, _)| *s == scheme)
                .map(|(_, b)| *b)
                .ok_or_else(|| GpuError::NoShader(scheme.into()))?
        } else {
            bindings
        };
        let mut used: Vec<u32> = list.iter().map(|(b, _)| *b).collect();
        used.sort_unstable();
        out.insert(name.to_string(), used);
    }
    Ok(out)
}

/// A buffer larger than one storage binding is a typed error, never a
/// truncation.
pub(super) fn check(limits: &Limits, what: &'static str, bytes: u64) -> Result<(), GpuError> {
    if bytes > limits.max_storage_buffer_binding_size {
        Err(GpuError::BufferTooLarge {
            what,
            needed: bytes,
            max: limits.max_storage_buffer_binding_size,
        })
    } else {
        Ok(())
    }
}

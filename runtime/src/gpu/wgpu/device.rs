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
    // The limit errors name the adapter whose limit was exceeded (the same
    // request fits another device) and the limit, as wgpu spells it.
    #[error("the displacement map ({width}x{height}) exceeds max_texture_dimension_2d = {max} of {adapter}")]
    MapTooLarge {
        width: u32,
        height: u32,
        max: u32,
        adapter: String,
    },
    #[error("the stencil table ({width}x{height}) exceeds max_texture_dimension_2d = {max} of {adapter}")]
    TableTooLarge {
        width: u32,
        height: u32,
        max: u32,
        adapter: String,
    },
    #[error("{what} needs {needed} bytes in one binding, more than max_storage_buffer_binding_size = {max} of {adapter}")]
    BufferTooLarge {
        what: &'static str,
        needed: u64,
        max: u64,
        adapter: String,
    },
    #[error("{patches} patches need {chunks} workgroups of {CHUNK} in one dispatch of the GPU-driven buckets, more than max_workgroups_per_dimension = {max} of {adapter}")]
    TooManyChunks {
        patches: u64,
        chunks: u64,
        max: u32,
        adapter: String,
    },
    #[error("wgpu reported an error: {0}")]
    Wgpu(String),
    /// The device was lost (a driver reset, a removed GPU, or
    /// `Device::destroy`): every later operation fails with this error.
    #[error("the GPU device ({adapter}) was lost: {reason}; nothing was written")]
    DeviceLost { adapter: String, reason: String },
    /// The device could not allocate a buffer or texture.
    #[error("the GPU ({adapter}) is out of memory: {message}")]
    OutOfMemory { adapter: String, message: String },
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
    /// Why the device was lost, once it was (set by its lost callback).
    lost: std::sync::Arc<std::sync::Mutex<Option<String>>>,
    /// The first error no error scope caught (wgpu's default handler
    /// would panic), reported by the next [`Gpu::scoped`].
    uncaptured: std::sync::Arc<std::sync::Mutex<Option<String>>>,
    /// Pipelines tessgen created on this device ([`Gpu::pipelines_created`]).
    pipelines: std::sync::atomic::AtomicUsize,
}

impl Gpu {
    /// How many compute and render pipelines tessgen has created on this
    /// device: an engine's frame loop checks that none is made per frame.
    pub fn pipelines_created(&self) -> usize {
        self.pipelines.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// Count one pipeline creation.
    pub(crate) fn count_pipeline(&self) {
        self.pipelines
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }

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
        Ok(Gpu::from_parts(device, queue, info, limits))
    }

    /// A [`Gpu`] around a device the caller opened; its lost callback is
    /// taken over so that loss becomes [`GpuError::DeviceLost`].
    pub fn from_parts(
        device: wgpu::Device,
        queue: wgpu::Queue,
        info: wgpu::AdapterInfo,
        limits: Limits,
    ) -> Gpu {
        let lost = std::sync::Arc::new(std::sync::Mutex::new(None));
        let flag = lost.clone();
        device.set_device_lost_callback(move |reason, message| {
            if let Ok(mut l) = flag.lock() {
                *l = Some(match reason {
                    wgpu::DeviceLostReason::Destroyed => format!("destroyed ({message})"),
                    wgpu::DeviceLostReason::Unknown => format!("lost by the driver ({message})"),
                });
            }
        });
        let uncaptured = std::sync::Arc::new(std::sync::Mutex::new(None));
        let slot = uncaptured.clone();
        device.on_uncaptured_error(std::sync::Arc::new(move |e: wgpu::Error| {
            if let Ok(mut s) = slot.lock() {
                s.get_or_insert(e.to_string());
            }
        }));
        Gpu {
            device,
            queue,
            info,
            limits,
            lost,
            uncaptured,
            pipelines: Default::default(),
        }
    }

    /// The device is neither lost nor has an error outside a scope
    /// pending (which is taken: reported once).
    pub(crate) fn healthy(&self) -> Result<(), GpuError> {
        self.check_lost()?;
        let pending = self.uncaptured.lock().ok().and_then(|mut s| s.take());
        match pending {
            Some(e) => Err(self.or_lost(GpuError::Wgpu(e))),
            None => Ok(()),
        }
    }

    /// [`GpuError::DeviceLost`] once the device is lost.
    pub fn check_lost(&self) -> Result<(), GpuError> {
        let reason = self.lost.lock().ok().and_then(|l| l.clone());
        match reason {
            Some(reason) => Err(GpuError::DeviceLost {
                adapter: self.info.name.clone(),
                reason,
            }),
            None => Ok(()),
        }
    }

    /// `e`, unless the device was lost: then [`GpuError::DeviceLost`]
    /// (what a lost device's operations fail with is a symptom).
    pub(crate) fn or_lost(&self, e: GpuError) -> GpuError {
        // The lost callback runs on the next poll after the loss.
        let _ = self.device.poll(wgpu::PollType::Poll);
        self.check_lost().err().unwrap_or(e)
    }

    /// Run `f` and turn any wgpu validation or out-of-memory error it
    /// caused into a `GpuError` ([`GpuError::DeviceLost`] on a lost device).
    pub(crate) fn scoped<T>(&self, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        self.healthy()?;
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        let invalid = pollster::block_on(validation.pop());
        let full = pollster::block_on(oom.pop());
        if let Some(e) = full {
            return Err(self.or_lost(GpuError::OutOfMemory {
                adapter: self.info.name.clone(),
                message: e.to_string(),
            }));
        }
        match invalid {
            Some(e) => Err(self.or_lost(GpuError::Wgpu(e.to_string()))),
            None => self.healthy().map(|()| out),
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
pub(super) fn check(
    adapter: &str,
    limits: &Limits,
    what: &'static str,
    bytes: u64,
) -> Result<(), GpuError> {
    if bytes > limits.max_storage_buffer_binding_size {
        Err(GpuError::BufferTooLarge {
            what,
            needed: bytes,
            max: limits.max_storage_buffer_binding_size,
            adapter: adapter.to_string(),
        })
    } else {
        Ok(())
    }
}

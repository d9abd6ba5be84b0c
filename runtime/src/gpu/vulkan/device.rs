//! The Vulkan instance, device and queue ([`Vulkan`]): the loader opened at
//! run time, a device with tessellation picked, one-shot command
//! submission; the harness's errors ([`VkError`]), the device limits it
//! checks ([`DeviceLimits`]) and the check of a scheme's pipeline against
//! them ([`check_limits`], [`per_patch_locations`]).

use crate::cpu;
use crate::gpu::capture::CaptureError;
use crate::gpu::upload::UploadError;
use crate::kernels::common::SchemeKernels;
use ash::vk;

use super::Vulkan;

/// Errors of the Vulkan harness.
#[derive(Debug, thiserror::Error)]
pub enum VkError {
    #[error("cannot load the Vulkan loader (install libvulkan1, and mesa-vulkan-drivers for lavapipe): {0}")]
    Loader(String),
    #[error("Vulkan call {call} failed: {result}")]
    Call {
        call: &'static str,
        result: vk::Result,
    },
    /// `VK_ERROR_DEVICE_LOST` from any call: the device is unusable.
    /// `device` names it (empty only before one was chosen).
    #[error("the Vulkan device{} was lost in {call} (a driver reset or a removed GPU); nothing was written", named(.device))]
    DeviceLost { call: &'static str, device: String },
    /// `VK_ERROR_OUT_OF_DEVICE_MEMORY` / `VK_ERROR_OUT_OF_HOST_MEMORY`.
    #[error("the Vulkan device{} ran out of memory in {call}: {result}", named(.device))]
    OutOfMemory {
        call: &'static str,
        result: vk::Result,
        device: String,
    },
    #[error("no Vulkan device supports tessellationShader and vertexPipelineStoresAndAtomics with a graphics+compute queue (install mesa-vulkan-drivers for lavapipe)")]
    NoDevice,
    #[error("no Vulkan device matches TESSGEN_VK_DEVICE={0:?}")]
    DeviceNotFound(String),
    #[error("glslangValidator could not be run ({0}); install glslang-tools")]
    NoGlslang(String),
    #[error("glslangValidator failed on {file} (stage {stage}):\n{log}")]
    Compile {
        file: String,
        stage: &'static str,
        log: String,
    },
    #[error("no {language} shader {file} for scheme `{scheme}` in this build")]
    NoShader {
        language: &'static str,
        scheme: String,
        file: String,
    },
    /// A device limit the request exceeds, named as Vulkan spells it,
    /// with the device (the same request may fit another).
    #[error("scheme `{scheme}`: {what} needs {needed}, {device} allows {max}")]
    Limit {
        scheme: String,
        what: &'static str,
        needed: u64,
        max: u64,
        device: String,
    },
    #[error("no Vulkan memory type for {0}")]
    NoMemoryType(&'static str),
    #[error("i/o: {0}")]
    Io(String),
    #[error(transparent)]
    Tess(#[from] cpu::TessError),
    #[error("positions: expected {expected}, got {got}")]
    PositionCount { expected: usize, got: usize },
    /// The upload was refused for another reason (a refinement stencil
    /// table that does not fit the mesh).
    #[error(transparent)]
    Upload(UploadError),
    #[error("scheme `{scheme}` has a triangle domain: the hardware's inner vertices are not grid points, so capture its triangles with evaluate_triangles")]
    TriangleDomain { scheme: String },
    #[error("scheme `{scheme}` has a quad domain: evaluate_triangles is for triangle schemes")]
    QuadDomain { scheme: String },
    #[error(
        "the Vulkan device has no geometryShader, which the triangle and adaptive captures need"
    )]
    NoGeometryShader,
    #[error("level {level}: the tessellator emitted {emitted} triangles for {patches} patches, more than the {capacity} the capture holds")]
    CaptureOverflow {
        level: u32,
        patches: u64,
        emitted: u64,
        capacity: u64,
    },
    #[error(transparent)]
    Capture(#[from] CaptureError),
    #[error("explicit edge factors: the mesh has {expected} edges, {got} factors were given")]
    EdgeFactorCount { expected: usize, got: usize },
    #[error("adaptive draws need VkMesh::evaluate_adaptive (the samples are not a grid)")]
    AdaptiveNotGrid,
}

impl From<UploadError> for VkError {
    fn from(e: UploadError) -> Self {
        match e {
            UploadError::Tess(e) => VkError::Tess(e),
            UploadError::PositionCount { expected, got } => {
                VkError::PositionCount { expected, got }
            }
            e @ UploadError::Refinement { .. } => VkError::Upload(e),
        }
    }
}

/// The error of a failed Vulkan call: device loss and exhausted memory
/// typed, anything else with the call and its result. The device is named
/// where the call's result leaves the harness ([`VkError::on_device`]).
pub(super) fn call(call: &'static str) -> impl FnOnce(vk::Result) -> VkError {
    move |result| match result {
        vk::Result::ERROR_DEVICE_LOST => VkError::DeviceLost {
            call,
            device: String::new(),
        },
        vk::Result::ERROR_OUT_OF_DEVICE_MEMORY | vk::Result::ERROR_OUT_OF_HOST_MEMORY => {
            VkError::OutOfMemory {
                call,
                result,
                device: String::new(),
            }
        }
        result => VkError::Call { call, result },
    }
}

/// ` (NAME)` for a named device, nothing before one was chosen.
fn named(device: &str) -> String {
    if device.is_empty() {
        String::new()
    } else {
        format!(" ({device})")
    }
}

impl VkError {
    /// A device loss or exhausted memory named after `device` (the public
    /// entry points of the harness pass their errors through this, so the
    /// calls deep inside need not carry the name).
    pub(super) fn on_device(self, name: &str) -> VkError {
        match self {
            VkError::DeviceLost { call, device } if device.is_empty() => VkError::DeviceLost {
                call,
                device: name.to_string(),
            },
            VkError::OutOfMemory {
                call,
                result,
                device,
            } if device.is_empty() => VkError::OutOfMemory {
                call,
                result,
                device: name.to_string(),
            },
            e => e,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Loss and memory exhaustion, which lavapipe cannot be made to
    /// produce, are typed wherever a call returns them, and name the device
    /// once they leave the harness's entry points.
    #[test]
    fn failed_calls_are_typed() {
        let lost = call("vkQueueSubmit")(vk::Result::ERROR_DEVICE_LOST);
        assert!(matches!(
            lost,
            VkError::DeviceLost {
                call: "vkQueueSubmit",
                ..
            }
        ));
        assert_eq!(
            lost.to_string(),
            "the Vulkan device was lost in vkQueueSubmit (a driver reset or a removed GPU); nothing was written"
        );
        let named = lost.on_device("llvmpipe (LLVM 19)");
        assert_eq!(
            named.to_string(),
            "the Vulkan device (llvmpipe (LLVM 19)) was lost in vkQueueSubmit (a driver reset or a removed GPU); nothing was written"
        );
        // A name once given stays.
        assert!(named
            .on_device("another")
            .to_string()
            .contains("(llvmpipe (LLVM 19))"));
        for r in [
            vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
            vk::Result::ERROR_OUT_OF_HOST_MEMORY,
        ] {
            let e = call("vkAllocateMemory")(r);
            assert!(matches!(e, VkError::OutOfMemory { .. }), "{e:?}");
            assert!(e
                .to_string()
                .starts_with("the Vulkan device ran out of memory in vkAllocateMemory"));
            assert!(e
                .on_device("gpu0")
                .to_string()
                .starts_with("the Vulkan device (gpu0) ran out of memory in vkAllocateMemory"));
        }
        let other = call("vkCreateInstance")(vk::Result::ERROR_INITIALIZATION_FAILED);
        assert!(matches!(other, VkError::Call { .. }), "{other:?}");
    }
}

/// The device limits the harness checks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DeviceLimits {
    pub max_tessellation_patch_size: u32,
    pub max_tessellation_generation_level: u32,
    pub max_tessellation_control_per_patch_output_components: u32,
    pub max_tessellation_evaluation_input_components: u32,
    pub max_storage_buffer_range: u32,
    pub max_image_dimension_2d: u32,
    pub max_compute_work_group_count_x: u32,
}

impl Vulkan {
    /// The first device with tessellation shaders and vertex-pipeline stores
    /// (or the one whose name contains `TESSGEN_VK_DEVICE`).
    pub fn new() -> Result<Vulkan, VkError> {
        // SAFETY: loading the system Vulkan loader; every handle created
        // below is destroyed in Drop, in reverse order.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| VkError::Loader(e.to_string()))?;
        let app = vk::ApplicationInfo::default()
            .application_name(c"tessgen")
            .api_version(vk::API_VERSION_1_1);
        let ci = vk::InstanceCreateInfo::default().application_info(&app);
        let instance =
            unsafe { entry.create_instance(&ci, None) }.map_err(call("vkCreateInstance"))?;
        // `entry` keeps the loader library loaded: it must outlive the
        // `destroy_instance` below (a moved-in `entry` was dropped, and the
        // loader unloaded, before it ran: a segfault whenever no device was
        // chosen, e.g. TESSGEN_VK_DEVICE naming none).
        match Self::with_instance(entry.clone(), instance.clone()) {
            Ok(v) => Ok(v),
            Err(e) => {
                unsafe { instance.destroy_instance(None) };
                drop(entry);
                Err(e)
            }
        }
    }

    fn with_instance(entry: ash::Entry, instance: ash::Instance) -> Result<Vulkan, VkError> {
        let devices = unsafe { instance.enumerate_physical_devices() }
            .map_err(call("vkEnumeratePhysicalDevices"))?;
        let want = std::env::var("TESSGEN_VK_DEVICE").ok();
        let mut chosen = None;
        for pd in devices {
            let props = unsafe { instance.get_physical_device_properties(pd) };
            let name = props
                .device_name_as_c_str()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            if let Some(w) = &want {
                if !name.to_lowercase().contains(&w.to_lowercase()) {
                    continue;
                }
            }
            let f = unsafe { instance.get_physical_device_features(pd) };
            if f.tessellation_shader == vk::FALSE
                || f.vertex_pipeline_stores_and_atomics == vk::FALSE
            {
                continue;
            }
            let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
            let Some(family) = families.iter().position(|q| {
                q.queue_flags
                    .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
            }) else {
                continue;
            };
            chosen = Some((pd, props, name, family as u32, f.geometry_shader));
            break;
        }
        let Some((pd, props, name, family, geometry_shader)) = chosen else {
            return Err(match want {
                Some(w) => VkError::DeviceNotFound(w),
                None => VkError::NoDevice,
            });
        };
        let features = vk::PhysicalDeviceFeatures {
            tessellation_shader: vk::TRUE,
            vertex_pipeline_stores_and_atomics: vk::TRUE,
            geometry_shader,
            ..Default::default()
        };
        let priorities = [1.0f32];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&priorities)];
        let dci = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_features(&features);
        let device =
            unsafe { instance.create_device(pd, &dci, None) }.map_err(call("vkCreateDevice"))?;
        let queue = unsafe { device.get_device_queue(family, 0) };
        let memory = unsafe { instance.get_physical_device_memory_properties(pd) };
        let setup = || -> Result<(vk::CommandPool, vk::CommandBuffer, vk::Fence), VkError> {
            let pool = unsafe {
                device.create_command_pool(
                    &vk::CommandPoolCreateInfo::default()
                        .queue_family_index(family)
                        .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER),
                    None,
                )
            }
            .map_err(call("vkCreateCommandPool"))?;
            let cmd = unsafe {
                device.allocate_command_buffers(
                    &vk::CommandBufferAllocateInfo::default()
                        .command_pool(pool)
                        .level(vk::CommandBufferLevel::PRIMARY)
                        .command_buffer_count(1),
                )
            }
            .map_err(call("vkAllocateCommandBuffers"))?[0];
            let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
                .map_err(call("vkCreateFence"))?;
            Ok((pool, cmd, fence))
        };
        let (pool, cmd, fence) = match setup() {
            Ok(x) => x,
            Err(e) => {
                unsafe { device.destroy_device(None) };
                return Err(e);
            }
        };
        let l = &props.limits;
        let driver = format!(
            "{name} (Vulkan {}.{}.{})",
            vk::api_version_major(props.api_version),
            vk::api_version_minor(props.api_version),
            vk::api_version_patch(props.api_version)
        );
        Ok(Vulkan {
            _entry: entry,
            instance,
            device,
            queue,
            memory,
            pool,
            cmd,
            fence,
            name: driver,
            geometry_shader: geometry_shader == vk::TRUE,
            limits: DeviceLimits {
                max_tessellation_patch_size: l.max_tessellation_patch_size,
                max_tessellation_generation_level: l.max_tessellation_generation_level,
                max_tessellation_control_per_patch_output_components: l
                    .max_tessellation_control_per_patch_output_components,
                max_tessellation_evaluation_input_components: l
                    .max_tessellation_evaluation_input_components,
                max_storage_buffer_range: l.max_storage_buffer_range,
                max_image_dimension_2d: l.max_image_dimension2_d,
                max_compute_work_group_count_x: l.max_compute_work_group_count[0],
            },
        })
    }

    /// Record `f` into the command buffer, submit it and wait.
    pub(super) fn submit(
        &self,
        f: impl FnOnce(&ash::Device, vk::CommandBuffer),
    ) -> Result<(), VkError> {
        let d = &self.device;
        unsafe {
            d.reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty())
                .map_err(call("vkResetCommandBuffer"))?;
            d.begin_command_buffer(
                self.cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )
            .map_err(call("vkBeginCommandBuffer"))?;
            // Earlier submissions' shader writes (vertex stage, uploads) are
            // visible to everything recorded here.
            let all = vk::MemoryBarrier::default()
                .src_access_mask(
                    vk::AccessFlags::SHADER_WRITE
                        | vk::AccessFlags::TRANSFER_WRITE
                        | vk::AccessFlags::HOST_WRITE,
                )
                .dst_access_mask(
                    vk::AccessFlags::SHADER_READ
                        | vk::AccessFlags::SHADER_WRITE
                        | vk::AccessFlags::UNIFORM_READ
                        | vk::AccessFlags::TRANSFER_READ
                        | vk::AccessFlags::TRANSFER_WRITE,
                );
            d.cmd_pipeline_barrier(
                self.cmd,
                vk::PipelineStageFlags::ALL_COMMANDS | vk::PipelineStageFlags::HOST,
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::DependencyFlags::empty(),
                &[all],
                &[],
                &[],
            );
            f(d, self.cmd);
            let to_host = vk::MemoryBarrier::default()
                .src_access_mask(vk::AccessFlags::SHADER_WRITE | vk::AccessFlags::TRANSFER_WRITE)
                .dst_access_mask(vk::AccessFlags::HOST_READ);
            d.cmd_pipeline_barrier(
                self.cmd,
                vk::PipelineStageFlags::ALL_COMMANDS,
                vk::PipelineStageFlags::HOST,
                vk::DependencyFlags::empty(),
                &[to_host],
                &[],
                &[],
            );
            d.end_command_buffer(self.cmd)
                .map_err(call("vkEndCommandBuffer"))?;
            let cmds = [self.cmd];
            d.queue_submit(
                self.queue,
                &[vk::SubmitInfo::default().command_buffers(&cmds)],
                self.fence,
            )
            .map_err(call("vkQueueSubmit"))?;
            let waited = d
                .wait_for_fences(&[self.fence], true, u64::MAX)
                .map_err(call("vkWaitForFences"));
            d.reset_fences(&[self.fence])
                .map_err(call("vkResetFences"))?;
            waited
        }
    }
}

impl Drop for Vulkan {
    fn drop(&mut self) {
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_fence(self.fence, None);
            self.device.destroy_command_pool(self.pool, None);
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}

/// The per-patch output locations a scheme's control stage writes: the
/// control points packed into `ceil(3·KMAX / 4)` `vec4`s, plus one for the
/// patch index the HLSL hull passes on; against the device's
/// `maxTessellationControlPerPatchOutputComponents / 4` locations (Vulkan's
/// "Shader Input and Output Locations" table).
pub fn per_patch_locations(scheme: &SchemeKernels) -> u32 {
    // The packing is the Plan's (`TessStages::slots`), printed into the
    // generated ABI per scheme. The harness runs built-in schemes only, all
    // in the table; a scheme missing from it cannot be laid out, so it
    // reports as not fitting any device.
    let slots = crate::abi::TESS_PATCH_SLOTS
        .iter()
        .find(|(name, _)| *name == scheme.name)
        .map_or(u32::MAX - 1, |(_, slots)| *slots);
    slots + 1
}

/// Check that a scheme's tessellation pipeline fits the device.
pub fn check_limits(scheme: &SchemeKernels, l: &DeviceLimits, device: &str) -> Result<(), VkError> {
    let locations = per_patch_locations(scheme) as u64;
    let limit = |what, needed: u64, max: u64| {
        if needed > max {
            Err(VkError::Limit {
                scheme: scheme.name.to_string(),
                what,
                needed,
                max,
                device: device.to_string(),
            })
        } else {
            Ok(())
        }
    };
    limit(
        "patch size (control points per input patch)",
        1,
        l.max_tessellation_patch_size as u64,
    )?;
    limit(
        "per-patch output locations of the control stage (maxTessellationControlPerPatchOutputComponents / 4)",
        locations,
        l.max_tessellation_control_per_patch_output_components as u64 / 4,
    )?;
    limit(
        "input locations of the evaluation stage (maxTessellationEvaluationInputComponents / 4)",
        locations,
        l.max_tessellation_evaluation_input_components as u64 / 4,
    )
}

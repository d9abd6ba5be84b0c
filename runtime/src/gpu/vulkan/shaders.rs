//! Shader compilation: glslangValidator on the emitted GLSL/HLSL (to SPIR-V,
//! with the harness's defines), the harness's one capture geometry shader,
//! and the [`VkMesh`] shader modules built from them.

use crate::abi::binding;
use crate::gpu::capture::VERTEX_FLOATS;
use crate::kernels;
use ash::vk;
use std::ffi::CStr;
use std::path::PathBuf;
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};

use super::device::{call, VkError};
use super::{Language, VkMesh, CAPTURE};

/// The harness's one geometry shader (not a generated file), for every
/// draw whose tessellated vertices are not a grid: triangle schemes (their
/// inner rings are not the lattice) and adaptive draws of any scheme. It
/// receives every triangle the tessellator emitted, with the evaluation
/// stage's outputs at the locations both emitted languages write (GLSL
/// `te_normal` 0, `te_position` 1, and with `-DTESSGEN_CAPTURE` `te_domain`
/// 2, `te_patch` 3; HLSL `DsOut` in declaration order), and appends it to
/// the capture buffer (binding 20, `binding::TRIANGLES`): a `u32` triangle
/// counter bumped atomically, the capacity, then `VERTEX_FLOATS` floats per
/// vertex. A triangle past the capacity is counted but not written, so the
/// host can tell an overflow from a full buffer. The domain point is
/// barycentric `(x, y, z)` for triangles and `(u, v, 0)` for quads, so the
/// host can evaluate the CPU surface at every captured vertex (parity).
///
/// The binding and the vertex stride are filled in from
/// [`binding::TRIANGLES`] and [`VERTEX_FLOATS`] (`capture_geometry_shader`),
/// so the GLSL and the host's reading of the buffer cannot disagree.
const CAPTURE_GEOMETRY_TEMPLATE: &str = r#"#version 450
layout(triangles) in;
layout(points, max_vertices = 1) out;

layout(location = 0) in vec3 te_normal[];
layout(location = 1) in vec3 te_position[];
layout(location = 2) in vec3 te_domain[];
layout(location = 3) flat in uint te_patch[];

layout(std430, set = 0, binding = @TRIANGLES@) buffer Capture {
    uint triangles;
    uint capacity;
    uint pad0;
    uint pad1;
    float data[];
};

void main() {
    uint t = atomicAdd(triangles, 1u);
    if (t >= capacity) {
        return;
    }
    for (uint k = 0u; k < 3u; k += 1u) {
        uint o = (3u * t + k) * @VERTEX_FLOATS@u;
        data[o + 0u] = te_position[k].x;
        data[o + 1u] = te_position[k].y;
        data[o + 2u] = te_position[k].z;
        data[o + 3u] = te_normal[k].x;
        data[o + 4u] = te_normal[k].y;
        data[o + 5u] = te_normal[k].z;
        data[o + 6u] = te_domain[k].x;
        data[o + 7u] = te_domain[k].y;
        data[o + 8u] = te_domain[k].z;
        data[o + 9u] = uintBitsToFloat(te_patch[k]);
    }
}
"#;

/// [`CAPTURE_GEOMETRY_TEMPLATE`] with the capture binding and stride.
pub(super) fn capture_geometry_shader() -> &'static str {
    static SOURCE: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    SOURCE.get_or_init(|| {
        CAPTURE_GEOMETRY_TEMPLATE
            .replace("@TRIANGLES@", &binding::TRIANGLES.to_string())
            .replace("@VERTEX_FLOATS@", &VERTEX_FLOATS.to_string())
    })
}

/// glslangValidator on one emitted shader, to SPIR-V words.
pub(super) fn compile(
    source: &str,
    file: &str,
    stage: &'static str,
    entry: Option<&str>,
    defines: &[String],
) -> Result<Vec<u32>, VkError> {
    static SEQ: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "tessgen-vk-{}-{}",
        std::process::id(),
        SEQ.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).map_err(|e| VkError::Io(format!("{}: {e}", dir.display())))?;
    let name = file.replace('/', "_");
    let src: PathBuf = dir.join(&name);
    let spv = dir.join(format!("{name}.{stage}.spv"));
    let result = (|| {
        std::fs::write(&src, source).map_err(|e| VkError::Io(format!("{}: {e}", src.display())))?;
        let mut cmd = Command::new("glslangValidator");
        cmd.args(["-V", "--target-env", "vulkan1.1", "-S", stage]);
        if let Some(e) = entry {
            // HLSL source, this entry point.
            cmd.args(["-D", "-e", e]);
        }
        cmd.arg(format!("-D{CAPTURE}"));
        for d in defines {
            cmd.arg(format!("-D{d}"));
        }
        cmd.arg(&src).arg("-o").arg(&spv);
        let out = cmd
            .output()
            .map_err(|e| VkError::NoGlslang(e.to_string()))?;
        if !out.status.success() {
            return Err(VkError::Compile {
                file: file.to_string(),
                stage,
                log: format!(
                    "{}{}",
                    String::from_utf8_lossy(&out.stdout),
                    String::from_utf8_lossy(&out.stderr)
                ),
            });
        }
        let bytes =
            std::fs::read(&spv).map_err(|e| VkError::Io(format!("{}: {e}", spv.display())))?;
        ash::util::read_spv(&mut std::io::Cursor::new(bytes))
            .map_err(|e| VkError::Io(format!("{}: {e}", spv.display())))
    })();
    let _ = std::fs::remove_dir_all(&dir);
    result
}

impl<'v> VkMesh<'v> {
    /// Source, file name and entry point of a stage of the emitted shaders.
    fn shader(
        &self,
        stage: &'static str,
    ) -> Result<(String, &'static str, Option<&'static str>), VkError> {
        let s = self.scheme.name;
        let (file, entry) = match self.options.language {
            Language::Glsl => (
                match stage {
                    "comp" => format!("glsl/{s}_vertex_stage.comp"),
                    "patch" => format!("glsl/{s}_patch.comp"),
                    "eval" => format!("glsl/{s}_eval.comp"),
                    "refine" => format!("glsl/{s}_refine.comp"),
                    other => format!("glsl/{s}.{other}"),
                },
                None,
            ),
            Language::Hlsl => (
                format!("hlsl/{s}.hlsl"),
                Some(match stage {
                    "vert" => "vs_main",
                    "tesc" => "hs_main",
                    "tese" => "ds_main",
                    "patch" => "patch_main",
                    "eval" => "eval_main",
                    "refine" => "refine_main",
                    _ => "vertex_stage_main",
                }),
            ),
        };
        let source = kernels::shader(&file).ok_or_else(|| VkError::NoShader {
            language: self.options.language.name(),
            scheme: s.into(),
            file: file.clone(),
        })?;
        Ok((file, source, entry))
    }

    pub(super) fn module(
        &mut self,
        stage: &'static str,
    ) -> Result<(vk::ShaderModule, &'static CStr), VkError> {
        let (file, source, entry) = if stage == "geom" {
            (
                "harness/capture_triangles.geom".to_string(),
                capture_geometry_shader(),
                None,
            )
        } else {
            self.shader(stage)?
        };
        // The compute patch and evaluation stages are compute shaders like
        // the vertex stage.
        let glslang_stage = if matches!(stage, "patch" | "eval" | "refine") {
            "comp"
        } else {
            stage
        };
        let words = compile(
            source,
            &file,
            glslang_stage,
            entry,
            &self.options.all_defines(),
        )?;
        let m = unsafe {
            self.vk
                .device
                .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&words), None)
        }
        .map_err(call("vkCreateShaderModule"))?;
        self.modules.push(m);
        let name: &'static CStr = match entry {
            None => c"main",
            Some("vs_main") => c"vs_main",
            Some("hs_main") => c"hs_main",
            Some("ds_main") => c"ds_main",
            Some("patch_main") => c"patch_main",
            Some("eval_main") => c"eval_main",
            Some("refine_main") => c"refine_main",
            Some(_) => c"vertex_stage_main",
        };
        Ok((m, name))
    }
}

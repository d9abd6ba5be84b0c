//! Every emitted WGSL module parses and validates with naga, has every
//! entry point, and translates through naga's MSL, HLSL, SPIR-V and GLSL
//! back ends for every entry point (the portability check); the SPIR-V
//! passes `spirv-val` and the GLSL compiles with `glslangValidator`. Each
//! entry point stays within WebGPU's default limits: at most 8 storage
//! buffers per shader stage, no writable storage in the vertex stage, no two
//! resources at one binding. Checked for the built-in schemes and for a user
//! scheme declared with `scheme!` whose local names collide with WGSL
//! reserved words, built-ins and the module's globals.
//!
//! The tools come from spirv-tools and glslang-tools (`scripts/test.sh`
//! installs them); a missing tool fails the test, it never skips.

use naga::back::{glsl, hlsl, msl, spv};
use naga::valid::{Capabilities, GlobalUse, ModuleInfo, ValidationFlags, Validator};
use naga::{AddressSpace, Module, ShaderStage, StorageAccess};
use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use tessgen_codegen::backend::wgsl::{ADAPTIVE_ENTRY_POINTS, ENTRY_POINTS};
use tessgen_codegen::{Builder, GeneratedFile, SchemeSource, Target};
use tessgen_macros::scheme;

/// WebGPU's default `maxStorageBuffersPerShaderStage`.
const MAX_STORAGE_BUFFERS_PER_STAGE: usize = 8;

fn wgsl_files(builder: Builder) -> Vec<GeneratedFile> {
    let out = builder
        .target(Target::Wgsl)
        .command("tessgen generate --out generated")
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    out.files
        .into_iter()
        .filter(|f| f.path.starts_with("wgsl/"))
        .collect()
}

fn text(f: &GeneratedFile) -> String {
    String::from_utf8(f.contents.clone()).unwrap_or_else(|e| panic!("{}: {e}", f.path))
}

static COUNTER: AtomicUsize = AtomicUsize::new(0);

fn temp_path(name: &str) -> PathBuf {
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    std::env::temp_dir().join(format!(
        "tessgen_wgsl_{}_{n}_{}",
        std::process::id(),
        name.replace('/', "_")
    ))
}

fn run(tool: &str, args: &[&str]) -> Result<(), String> {
    let out = Command::new(tool).args(args).output().map_err(|e| {
        format!(
            "cannot run `{tool}` ({e}); install it (apt-get install spirv-tools glslang-tools, \
             or run scripts/test.sh)"
        )
    })?;
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "`{tool} {}` failed ({}):\n{}{}",
            args.join(" "),
            out.status,
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// Parse and validate with every validation flag.
fn parse_validate(path: &str, src: &str) -> Result<(Module, ModuleInfo), String> {
    let module = naga::front::wgsl::parse_str(src)
        .map_err(|e| format!("{path}: parse error:\n{}", e.emit_to_string(src)))?;
    let info = Validator::new(ValidationFlags::all(), Capabilities::default())
        .validate(&module)
        .map_err(|e| format!("{path}: validation error:\n{}", e.emit_to_string(src)))?;
    Ok((module, info))
}

fn stage_name(s: ShaderStage) -> &'static str {
    match s {
        ShaderStage::Vertex => "vertex",
        ShaderStage::Fragment => "fragment",
        ShaderStage::Compute => "compute",
        _ => "other",
    }
}

/// The module's entry points as `(name, stage)`, in declaration order.
fn entry_points(module: &Module) -> Vec<(String, String)> {
    module
        .entry_points
        .iter()
        .map(|ep| (ep.name.clone(), stage_name(ep.stage).to_string()))
        .collect()
}

/// One resource an entry point reaches.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Use {
    binding: u32,
    name: String,
    /// `Some(writable)` for storage buffers.
    storage: Option<bool>,
    written: bool,
}

/// The resources (bound globals) statically used by entry point `i`.
fn resources(module: &Module, info: &ModuleInfo, i: usize) -> Vec<Use> {
    let fi = info.get_entry_point(i);
    let mut out = Vec::new();
    for (h, var) in module.global_variables.iter() {
        let usage = fi[h];
        let Some(binding) = &var.binding else {
            continue;
        };
        if usage.is_empty() {
            continue;
        }
        let storage = match var.space {
            AddressSpace::Storage { access } => Some(access.contains(StorageAccess::STORE)),
            _ => None,
        };
        out.push(Use {
            binding: binding.binding,
            name: var.name.clone().unwrap_or_default(),
            storage,
            written: usage.contains(GlobalUse::WRITE),
        });
    }
    out.sort();
    out
}

/// WebGPU limits per entry point; `Err` lists every violation.
fn check_limits(path: &str, module: &Module, info: &ModuleInfo) -> Result<(), String> {
    let mut errors = Vec::new();
    for (i, ep) in module.entry_points.iter().enumerate() {
        let uses = resources(module, info, i);
        let storage: Vec<&Use> = uses.iter().filter(|u| u.storage.is_some()).collect();
        if storage.len() > MAX_STORAGE_BUFFERS_PER_STAGE {
            errors.push(format!(
                "{path}: {} uses {} storage buffers (WebGPU default limit {MAX_STORAGE_BUFFERS_PER_STAGE}): {:?}",
                ep.name,
                storage.len(),
                storage.iter().map(|u| &u.name).collect::<Vec<_>>()
            ));
        }
        if ep.stage != ShaderStage::Compute {
            for u in &storage {
                if u.storage == Some(true) {
                    errors.push(format!(
                        "{path}: {} ({}) uses writable storage buffer `{}`",
                        ep.name,
                        stage_name(ep.stage),
                        u.name
                    ));
                }
            }
        }
        let bindings: BTreeSet<u32> = uses.iter().map(|u| u.binding).collect();
        if bindings.len() != uses.len() {
            errors.push(format!(
                "{path}: {} uses two resources at one binding: {uses:?}",
                ep.name
            ));
        }
    }
    if errors.is_empty() {
        Ok(())
    } else {
        Err(errors.join("\n"))
    }
}

/// Translate every entry point through naga's MSL, HLSL, SPIR-V and GLSL
/// back ends; validate the SPIR-V with `spirv-val` and the GLSL with
/// `glslangValidator`.
fn translate(path: &str, module: &Module, info: &ModuleInfo) -> Result<(), String> {
    let mut errors = Vec::new();
    for ep in &module.entry_points {
        let what = format!("{path}: {} ({})", ep.name, stage_name(ep.stage));

        let msl_options = msl::Options {
            lang_version: (2, 0),
            ..Default::default()
        };
        let msl_pipeline = msl::PipelineOptions {
            entry_point: Some((ep.stage, ep.name.clone())),
            ..Default::default()
        };
        if let Err(e) = msl::write_string(module, info, &msl_options, &msl_pipeline) {
            errors.push(format!("{what}: MSL: {e}"));
        }

        let hlsl_options = hlsl::Options::default();
        let hlsl_pipeline = hlsl::PipelineOptions {
            entry_point: Some((ep.stage, ep.name.clone())),
        };
        let mut hlsl_out = String::new();
        let mut writer = hlsl::Writer::new(&mut hlsl_out, &hlsl_options, &hlsl_pipeline);
        if let Err(e) = writer.write(module, info, None) {
            errors.push(format!("{what}: HLSL: {e}"));
        }

        let spv_pipeline = spv::PipelineOptions {
            shader_stage: ep.stage,
            entry_point: ep.name.clone(),
        };
        match spv::write_vec(module, info, &spv::Options::default(), Some(&spv_pipeline)) {
            Err(e) => errors.push(format!("{what}: SPIR-V: {e}")),
            Ok(words) => {
                let file = temp_path(&format!("{path}.{}.spv", ep.name));
                let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
                let result = std::fs::write(&file, bytes)
                    .map_err(|e| format!("{}: {e}", file.display()))
                    .and_then(|()| {
                        run(
                            "spirv-val",
                            &["--target-env", "vulkan1.1", &file.to_string_lossy()],
                        )
                    });
                let _ = std::fs::remove_file(&file);
                if let Err(e) = result {
                    errors.push(format!("{what}: {e}"));
                }
            }
        }

        // OpenGL ES 3.10, what wgpu's GL back end asks naga for.
        let glsl_options = glsl::Options {
            version: glsl::Version::new_gles(310),
            ..Default::default()
        };
        let glsl_pipeline = glsl::PipelineOptions {
            shader_stage: ep.stage,
            entry_point: ep.name.clone(),
            multiview: None,
        };
        let mut glsl_out = String::new();
        let written = glsl::Writer::new(
            &mut glsl_out,
            module,
            info,
            &glsl_options,
            &glsl_pipeline,
            naga::proc::BoundsCheckPolicies::default(),
        )
        .and_then(|mut w| w.write());
        match written {
            Err(e) => errors.push(format!("{what}: GLSL: {e}")),
            Ok(_) => {
                let stage = match ep.stage {
                    ShaderStage::Vertex => "vert",
                    ShaderStage::Fragment => "frag",
                    _ => "comp",
                };
                let file = temp_path(&format!("{path}.{}.{stage}", ep.name));
                let result = std::fs::write(&file, &glsl_out)
                    .map_err(|e| format!("{}: {e}", file.display()))
                    .and_then(|()| {
                        run("glslangValidator", &["-S", stage, &file.to_string_lossy()])
                    });
                let _ = std::fs::remove_file(&file);
                if let Err(e) = result {
                    errors.push(format!("{what}: {e}"));
                }
            }
        }
    }
    if errors.is_empty() {
        Ok(())
    } else {
        Err(errors.join("\n\n"))
    }
}

/// Every check on one file; `Err` carries all messages.
fn validate(file: &GeneratedFile) -> Result<(), String> {
    let src = text(file);
    let (module, info) = parse_validate(&file.path, &src)?;
    // Every scheme, quads and triangles, also has the adaptive instanced
    // path's entries.
    let adaptive = ADAPTIVE_ENTRY_POINTS;
    let expected: Vec<(String, String)> = ENTRY_POINTS
        .iter()
        .chain(adaptive)
        .map(|(n, s)| (n.to_string(), s.to_string()))
        .collect();
    let found = entry_points(&module);
    if found != expected {
        return Err(format!(
            "{}: entry points {found:?}, expected {expected:?}",
            file.path
        ));
    }
    check_limits(&file.path, &module, &info)?;
    translate(&file.path, &module, &info)
}

/// Validate every file (in parallel) and report all failures together.
fn validate_all(files: &[GeneratedFile]) {
    let errors: Vec<String> = std::thread::scope(|s| {
        let handles: Vec<_> = files.iter().map(|f| s.spawn(|| validate(f))).collect();
        handles
            .into_iter()
            .filter_map(|h| h.join().unwrap_or_else(|_| Err("panicked".into())).err())
            .collect()
    });
    assert!(
        errors.is_empty(),
        "{} of {} WGSL files failed validation:\n\n{}",
        errors.len(),
        files.len(),
        errors.join("\n\n")
    );
}

fn paths(files: &[GeneratedFile]) -> Vec<String> {
    let mut p: Vec<String> = files.iter().map(|f| f.path.clone()).collect();
    p.sort();
    p
}

#[test]
fn builtin_schemes_validate() {
    let files = wgsl_files(Builder::new().builtin_schemes());
    assert_eq!(
        paths(&files),
        [
            "wgsl/acc.wgsl",
            "wgsl/g1cc.wgsl",
            "wgsl/gregory.wgsl",
            "wgsl/gregory_osd.wgsl",
            "wgsl/pccm.wgsl",
            "wgsl/phong.wgsl",
            "wgsl/pn.wgsl",
            "wgsl/regular.wgsl",
            "wgsl/stpn.wgsl"
        ]
    );
    validate_all(&files);
}

/// The bindings each entry point reaches, as `binding name access`: the
/// table a runtime builds its bind group layouts from.
#[test]
fn entry_point_bindings() {
    let files = wgsl_files(Builder::new().builtin_schemes());
    for f in &files {
        let src = text(f);
        let (module, info) = parse_validate(&f.path, &src).unwrap_or_else(|e| panic!("{e}"));
        for (i, ep) in module.entry_points.iter().enumerate() {
            let got: Vec<String> = resources(&module, &info, i)
                .iter()
                .map(|u| {
                    let access = match u.storage {
                        Some(true) => "read_write",
                        Some(false) => "read",
                        None => "-",
                    };
                    format!("{} {} {access}", u.binding, u.name)
                })
                .collect();
            let want: &[&str] = match ep.name.as_str() {
                // The refinement stage: the stencils in, the refined
                // positions out (6 bindings, 5 storage buffers).
                "refine_main" => &[
                    "10 params -",
                    "34 refine_base read",
                    "35 refine_offsets read",
                    "36 refine_indices read",
                    "37 refine_weights read",
                    "38 refined_positions read_write",
                ],
                "vertex_stage_main" => &[
                    "0 positions read",
                    "1 valence read",
                    "2 ring_offsets read",
                    "3 ring read",
                    "4 vertex_out_offsets read",
                    "5 vertex_out read_write",
                    "9 stencil_table -",
                    "10 params -",
                    // Crease and corner vertices: the sector records
                    // (8 storage buffers, WebGPU's default limit).
                    "31 vertex_sectors read",
                    "32 sectors read",
                ],
                // Scalar-tagged PN also reads the tags, crease vectors and
                // side signs: 8 storage buffers, WebGPU's default limit.
                "patch_main" if f.path == "wgsl/stpn.wgsl" => &[
                    "0 positions read",
                    "6 corner_vertex read",
                    "8 control_points read_write",
                    "10 params -",
                    "11 patch_faces read",
                    "13 normals read",
                    "14 tags read",
                    "15 crease read",
                    "16 corner_side read",
                ],
                // Triangle schemes: positions and normals at the corners.
                "patch_main" if ["wgsl/pn.wgsl", "wgsl/phong.wgsl"].contains(&f.path.as_str()) => {
                    &[
                        "0 positions read",
                        "6 corner_vertex read",
                        "8 control_points read_write",
                        "10 params -",
                        "11 patch_faces read",
                        "13 normals read",
                    ]
                }
                "patch_main" if f.path == "wgsl/regular.wgsl" => &[
                    "1 valence read",
                    "4 vertex_out_offsets read",
                    "5 vertex_out_ro read",
                    "6 corner_vertex read",
                    "7 corner_sector read",
                    "8 control_points read_write",
                    "10 params -",
                    "11 patch_faces read",
                ],
                // The c-patch reads per-valence constants from the table,
                // at each corner's `corner_valence` (8 storage buffers).
                "patch_main" => &[
                    "1 valence read",
                    "4 vertex_out_offsets read",
                    "5 vertex_out_ro read",
                    "6 corner_vertex read",
                    "7 corner_sector read",
                    "8 control_points read_write",
                    "9 stencil_table -",
                    "10 params -",
                    "11 patch_faces read",
                    "33 corner_valence read",
                ],
                // Every scheme (quads and triangles) evaluates through
                // eval_displaced: the face,
                // texture coordinates, owners, parameters and the map
                // (6 storage buffers in eval_main, 5 in the vertex stage).
                "eval_main" => &[
                    "8 control_points_ro read",
                    "10 params -",
                    "11 patch_faces read",
                    "12 samples read_write",
                    "21 texcoords read",
                    "22 owners read",
                    "23 displace_info read",
                    "24 displace_map -",
                ],
                "eval_vs" => &[
                    "8 control_points_ro read",
                    "10 params -",
                    "11 patch_faces read",
                    "21 texcoords read",
                    "22 owners read",
                    "23 displace_info read",
                    "24 displace_map -",
                ],
                // The wireframe flag.
                "shade_fs" => &["10 params -"],
                // Adaptive instanced path: the classify pass reads the
                // patch corners, vertices, edge ids, factors and metric
                // parameters, writes the levels (7 storage buffers, under
                // WebGPU's default 8); the evaluation reads the draw list
                // and, through eval_adaptive_displaced, the face and the
                // displacement data (7 storage buffers in
                // eval_adaptive_main).
                "adaptive_classify_main" => &[
                    "6 corner_vertex read",
                    "8 control_points_ro read",
                    "10 params -",
                    "11 patch_faces read",
                    "17 face_edges read",
                    "18 edge_factors read",
                    "19 adaptive read",
                    "25 patch_levels read_write",
                ],
                "eval_adaptive_main" => &[
                    "8 control_points_ro read",
                    "10 params -",
                    "11 patch_faces read",
                    "12 samples read_write",
                    "21 texcoords read",
                    "22 owners read",
                    "23 displace_info read",
                    "24 displace_map -",
                    "26 bucket_patches read",
                ],
                "eval_adaptive_vs" => &[
                    "8 control_points_ro read",
                    "10 params -",
                    "11 patch_faces read",
                    "21 texcoords read",
                    "22 owners read",
                    "23 displace_info read",
                    "24 displace_map -",
                    "26 bucket_patches read",
                ],
                // GPU-driven buckets: counting reads the levels and writes
                // the per-chunk counts, the plan pass scans them into
                // offsets and writes the lists' header and the indirect
                // arguments, scattering reads the levels and the offsets
                // and writes the lists; the indirect evaluation reads the
                // lists as bucket_patches.
                "adaptive_count_main" => &[
                    "10 params -",
                    "25 patch_levels read_write",
                    "30 bucket_chunks read_write",
                ],
                "adaptive_plan_main" => &[
                    "10 params -",
                    "27 bucket_list read_write",
                    "28 bucket_dispatch read_write",
                    "29 bucket_draw read_write",
                    "30 bucket_chunks read_write",
                ],
                "adaptive_scatter_main" => &[
                    "10 params -",
                    "25 patch_levels read_write",
                    "27 bucket_list read_write",
                    "30 bucket_chunks read_write",
                ],
                "eval_adaptive_indirect_main" => &[
                    "8 control_points_ro read",
                    "10 params -",
                    "11 patch_faces read",
                    "12 samples read_write",
                    "21 texcoords read",
                    "22 owners read",
                    "23 displace_info read",
                    "24 displace_map -",
                    "26 bucket_patches read",
                ],
                // Its drawn twin: the same lists, no samples.
                "eval_adaptive_indirect_vs" => &[
                    "8 control_points_ro read",
                    "10 params -",
                    "11 patch_faces read",
                    "21 texcoords read",
                    "22 owners read",
                    "23 displace_info read",
                    "24 displace_map -",
                    "26 bucket_patches read",
                ],
                other => panic!("{}: unexpected entry point {other}", f.path),
            };
            assert_eq!(got, want, "{}: {}", f.path, ep.name);
        }
    }
}

/// A user scheme (PCCM with renamed locals) whose local names are WGSL
/// reserved words (`filter`, `class`), a built-in function (`dot`) or
/// globals of the emitted module (`params`, the uniform block;
/// `control_points_ro`, a buffer): the printer must rename them.
fn user_scheme() -> SchemeSource {
    scheme! {
        /// PCCM with local names that are not valid as-is in WGSL.
        scheme pccm_user {
            facet quad;
            const c = cos(2 * pi / n);
            const s = sin(2 * pi / n);
            const sigma = (c + 5 + sqrt((c + 9) * (c + 1))) / 16;
            vertex {
                f[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;
                e[j] = (f[j - 1] + f[j]) / 2;
                v = (n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1])) / (n * (n + 5));
                t[j] = if n == 4 {
                    e[j]
                } else {
                    v + 4 * sigma / n * sum(k, cos(2 * pi * (k - j) / n) * e[k])
                };
            }
            patch ordinary: bicubic {
                out b00[i] = v(i);
                out b10[i] = e(i, 0);
                out b01[i] = e(i, 1);
                out b11[i] = f(i, 0);
            }
            patch extraordinary: cpatch {
                filter = sum(k, v(k) + 3 * e(k, 0) + 3 * e(k, 1) + 9 * f(k, 0)) / 64;
                class = filter;
                dot = class;
                params = dot;
                control_points_ro = params;
                kappa[i] = 3 / (4 * (s(i) + s(i + 1)));
                b310[i] = (v(i) + 3 * t(i, 0)) / 4;
                b130[i] = (v(i + 1) + 3 * t(i + 1, 1)) / 4;
                b211[i] = b310[i]
                    + (1 + c(i)) / 4 * (t(i + 1, 1) - t(i, 0))
                    + (1 - c(i + 1)) / 8 * (t(i, 0) - v(i))
                    + kappa[i] * (f(i, 0) - e(i, 0));
                b121[i] = b130[i]
                    + (1 + c(i + 1)) / 4 * (t(i, 0) - t(i + 1, 1))
                    + (1 - c(i)) / 8 * (t(i + 1, 1) - v(i + 1))
                    + kappa[i] * (f(i + 1, 0) - e(i + 1, 1));
                out v[i] = v(i);
                out t0[i] = t(i, 0);
                out t1[i] = t(i, 1);
                out b211[i] = b211[i];
                out b121[i] = b121[i];
                out b112[i] = control_points_ro
                    + 3 / 16 * (b211[i] + b121[i] - b211[i - 1] - b121[i + 1])
                    + 1 / 16 * (b211[i + 1] + b121[i - 1] - b211[i + 2] - b121[i + 2]);
            }
        }
    }
}

#[test]
fn user_scheme_validates() {
    let files = wgsl_files(Builder::new().scheme(user_scheme()));
    assert_eq!(paths(&files), ["wgsl/pccm_user.wgsl"]);
    let src = text(&files[0]);
    // The colliding names were renamed, not printed as-is.
    for renamed in [
        "let filter_: vec3<f32> = ",
        "let class_: vec3<f32> = filter_;",
        "let dot_: vec3<f32> = class_;",
        "let params_: vec3<f32> = dot_;",
        "let control_points_ro_: vec3<f32> = params_;",
    ] {
        assert!(
            src.contains(renamed),
            "`{renamed}` missing in pccm_user.wgsl"
        );
    }
    validate_all(&files);
}

/// A user scheme with only an extraordinary class: class 0 is then the
/// c-patch, drawn blue, and every dispatch chain has a single branch.
#[test]
fn single_class_scheme_validates() {
    let files = wgsl_files(Builder::new().scheme(SchemeSource::new(
        "test: cpatch only",
        r#"
        scheme cpatch_only {
            facet quad;
            const c = cos(2 * pi / n);
            const s = sin(2 * pi / n);
            vertex {
                f[j] = (4 * p + 2 * p[2 * j] + 2 * p[2 * j + 2] + p[2 * j + 1]) / 9;
                e[j] = (f[j - 1] + f[j]) / 2;
                v = (n * n * p + 4 * sum(k, p[2 * k]) + sum(k, p[2 * k + 1])) / (n * (n + 5));
            }
            patch extraordinary: cpatch {
                g = sum(k, v(k) + 3 * e(k, 0) + 3 * e(k, 1) + 9 * f(k, 0)) / 64;
                out v[i] = v(i);
                out t0[i] = e(i, 0);
                out t1[i] = e(i, 1);
                out b211[i] = f(i, 0);
                out b121[i] = f(i + 1, 0);
                out b112[i] = g + c(i) * (f(i, 0) - g) / 4 + s(i) * (f(i, 0) - g) / 4;
            }
        }
        "#,
    )));
    assert_eq!(paths(&files), ["wgsl/cpatch_only.wgsl"]);
    let src = text(&files[0]);
    assert!(
        !src.contains("base = vec3<f32>(1.0f, 0.55f, 0.1f)"),
        "no ordinary class, no orange"
    );
    assert!(src.contains("extraordinary_patch(face, (params.cp_base + (k * 24u)));"));
    validate_all(&files);
}

/// Negative controls: the checks must be able to fail.
#[test]
fn validation_rejects_broken_wgsl() {
    let bad = |src: &str| GeneratedFile {
        path: "wgsl/broken.wgsl".into(),
        contents: src.as_bytes().to_vec(),
    };
    // A type error.
    assert!(validate(&bad(
        "@compute @workgroup_size(1) fn main() { let x: u32 = 1.0f; }"
    ))
    .is_err());
    // A writable storage buffer in a vertex shader.
    let src = "@group(0) @binding(0) var<storage, read_write> b: array<f32>;\n\
               @vertex fn vs() -> @builtin(position) vec4<f32> { b[0] = 1.0f; return vec4<f32>(); }";
    let (m, i) = parse_validate("vs.wgsl", src).unwrap_or_else(|e| panic!("{e}"));
    let e = check_limits("vs.wgsl", &m, &i).err().unwrap_or_default();
    assert!(e.contains("writable storage buffer `b`"), "{e}");
    // Nine storage buffers in one compute entry point.
    let mut src = String::new();
    for k in 0..9 {
        src.push_str(&format!(
            "@group(0) @binding({k}) var<storage, read_write> b{k}: array<f32>;\n"
        ));
    }
    src.push_str("@compute @workgroup_size(1) fn main() {\n");
    for k in 0..9 {
        src.push_str(&format!("    b{k}[0] = 1.0f;\n"));
    }
    src.push_str("}\n");
    let (m, i) = parse_validate("nine.wgsl", &src).unwrap_or_else(|e| panic!("{e}"));
    let e = check_limits("nine.wgsl", &m, &i).err().unwrap_or_default();
    assert!(e.contains("uses 9 storage buffers"), "{e}");
}

/// The ABI's per-entry binding lists (`abi::WGSL_ENTRIES`, with
/// `patch_main` derived per scheme from the Plan) are exactly what naga
/// reflects from every emitted module: the bindings each entry uses, the
/// access of the variable it uses them through (bindings 5 and 8 are
/// declared twice, `read_write` and `read`), and the workgroup size. A
/// host that builds explicit bind group layouts from the lists (as
/// `generated/README.md` tells it to) then matches the shaders.
#[test]
fn abi_entry_bindings_match_naga() {
    use tessgen_codegen::backend::abi::{self, Access};
    let out = Builder::new()
        .builtin_schemes()
        .target(Target::Wgsl)
        .command("tessgen generate --out generated")
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    let mut checked = 0;
    for (m, entries) in &out.plan.schemes {
        let path = format!("wgsl/{}.wgsl", m.name);
        let file = out
            .file(&path)
            .unwrap_or_else(|| panic!("{path} not emitted"));
        let src = text(file);
        let module = naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{path}: {e}"));
        let info = Validator::new(ValidationFlags::all(), Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{path}: {e:?}"));
        let names: BTreeSet<&str> = module
            .entry_points
            .iter()
            .map(|e| e.name.as_str())
            .collect();
        let declared: BTreeSet<&str> = abi::WGSL_ENTRIES.iter().map(|e| e.name).collect();
        assert_eq!(names, declared, "{path}: entry points");
        for (i, ep) in module.entry_points.iter().enumerate() {
            let fi = info.get_entry_point(i);
            let mut used = Vec::new();
            for (h, var) in module.global_variables.iter() {
                if fi[h].is_empty() {
                    continue;
                }
                let Some(b) = &var.binding else { continue };
                let access = match var.space {
                    AddressSpace::Storage { access } if access.contains(StorageAccess::STORE) => {
                        Access::ReadWrite
                    }
                    _ => Access::Read,
                };
                let decl = abi::BINDINGS
                    .iter()
                    .find(|x| x.binding == b.binding)
                    .map(abi::wgsl_views)
                    .unwrap_or_default();
                let name = var.name.clone().unwrap_or_default();
                assert!(
                    decl.contains(&(name.clone(), access)),
                    "{path}: binding {} declared as {name} {access:?}, the ABI says {decl:?}",
                    b.binding
                );
                used.push((b.binding, access));
            }
            used.sort();
            let e = abi::wgsl_entry(&ep.name).unwrap_or_else(|| panic!("{}", ep.name));
            assert_eq!(
                used,
                abi::entry_bindings(&out.plan, m, entries, e),
                "{path}: bindings of {}",
                ep.name
            );
            let wg = if ep.stage == ShaderStage::Compute {
                ep.workgroup_size[0]
            } else {
                0
            };
            assert_eq!(
                wg, e.workgroup_size,
                "{path}: workgroup size of {}",
                ep.name
            );
            checked += 1;
        }
    }
    assert!(checked >= 8 * abi::WGSL_ENTRIES.len());
}

//! A foreign WebGPU host, written from `generated/README.md` alone: it reads
//! the cube's (and a mixed mesh's) OBJ, builds every input buffer with its own small half-edge /
//! ring / sector / corner builder following the README's "Building the
//! inputs" rules (not `runtime::topology`, `runtime::upload` or
//! `runtime::gpu`), uploads the stencil table from `generated/table/`,
//! runs `vertex_stage_main`, `patch_main` and `eval_main` of the checked-in
//! `generated/wgsl/<scheme>.wgsl` on wgpu with **explicit** bind group
//! layouts built from the ABI's per-entry binding lists (never `layout:
//! "auto"`), and gets the CPU tessellator's samples bit for bit.
//!
//! If this test needs a fact the README does not state, the README is
//! incomplete: fix the README (`codegen/src/backend/docs.rs`), not the test.

use std::collections::HashMap;
use std::path::PathBuf;
use tessgen_codegen::backend::abi::{self, Access, EntryPoint};
use tessgen_codegen::plan::{ConstValue, Entries, Module};
use tessgen_codegen::{Builder, Target};
use tessgen_runtime::tessellate::{tessellate, Request};
use tessgen_runtime::Mesh;

fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(path)
}

/// `v` and `f` lines of an OBJ (1-based, `a/b/c` forms allowed).
fn read_obj(path: &PathBuf) -> (Vec<[f32; 3]>, Vec<[u32; 4]>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let (mut v, mut f) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let mut w = line.split_whitespace();
        match w.next() {
            Some("v") => {
                let x: Vec<f32> = w.take(3).map(|s| s.parse().expect("a float")).collect();
                v.push([x[0], x[1], x[2]]);
            }
            Some("f") => {
                let x: Vec<u32> = w
                    .map(|s| {
                        s.split('/')
                            .next()
                            .unwrap_or("")
                            .parse::<u32>()
                            .expect("an index")
                            - 1
                    })
                    .collect();
                assert_eq!(x.len(), 4, "quads only");
                f.push([x[0], x[1], x[2], x[3]]);
            }
            _ => {}
        }
    }
    (v, f)
}

/// The input buffers of the README's "Building the inputs".
struct Inputs {
    positions: Vec<f32>,
    valence: Vec<u32>,
    ring_offsets: Vec<u32>,
    ring: Vec<u32>,
    vertex_out_offsets: Vec<u32>,
    vertex_out_points: u32,
    corner_vertex: Vec<u32>,
    corner_sector: Vec<u32>,
    patch_faces: Vec<u32>,
    /// Per class: (class, first, count, cp_base, points).
    classes: Vec<(u32, u32, u32, u32, u32)>,
    control_points: u32,
}

fn build_inputs(
    verts: &[[f32; 3]],
    faces: &[[u32; 4]],
    rows: (u32, u32),
    points: &[u32],
) -> Inputs {
    let nv = verts.len();
    let nh = 4 * faces.len();
    // Half-edge h = 4f + i runs v_i -> v_{i+1}.
    let origin = |h: usize| faces[h / 4][h % 4];
    let next = |h: usize| 4 * (h / 4) + (h % 4 + 1) % 4;
    let prev = |h: usize| 4 * (h / 4) + (h % 4 + 3) % 4;
    let dest = |h: usize| origin(next(h));
    let by_edge: HashMap<(u32, u32), usize> = (0..nh).map(|h| ((origin(h), dest(h)), h)).collect();
    let twin = |h: usize| by_edge[&(dest(h), origin(h))];
    let mut valence = vec![0u32; nv];
    for h in 0..nh {
        valence[origin(h) as usize] += 1;
    }
    // Sector 0: the smallest outgoing half-edge id; s_{j+1} = twin(prev(s_j)).
    let mut sector_of = vec![u32::MAX; nh];
    let (mut ring_offsets, mut ring) = (vec![0u32], Vec::new());
    let (mut vertex_out_offsets, mut total) = (Vec::new(), 0u32);
    for p in 0..nv as u32 {
        vertex_out_offsets.push(total);
        if let Some(s0) = (0..nh).find(|&h| origin(h) == p) {
            let n = valence[p as usize];
            ring.push(p);
            let mut s = s0;
            for j in 0..n {
                sector_of[s] = j;
                ring.push(dest(s));
                ring.push(dest(next(s)));
                s = twin(prev(s));
            }
            assert_eq!(s, s0, "one fan per vertex");
            total += rows.0 * n + rows.1;
        }
        ring_offsets.push(ring.len() as u32);
    }
    vertex_out_offsets.push(total);
    let corner_vertex: Vec<u32> = (0..nh).map(origin).collect();
    let corner_sector: Vec<u32> = sector_of.clone();
    // Classes: ordinary (0) when every corner has valence 4.
    let class_of: Vec<u32> = faces
        .iter()
        .map(|f| u32::from(!f.iter().all(|&v| valence[v as usize] == 4)))
        .collect();
    let (mut patch_faces, mut classes, mut cp) = (Vec::new(), Vec::new(), 0u32);
    for (c, &pts) in points.iter().enumerate() {
        let first = patch_faces.len() as u32;
        patch_faces.extend((0..faces.len() as u32).filter(|&f| class_of[f as usize] == c as u32));
        let count = patch_faces.len() as u32 - first;
        classes.push((c as u32, first, count, cp, pts));
        cp += count * pts;
    }
    Inputs {
        positions: verts.iter().flatten().copied().collect(),
        valence,
        ring_offsets,
        ring,
        vertex_out_offsets,
        vertex_out_points: total,
        corner_vertex,
        corner_sector,
        patch_faces,
        classes,
        control_points: cp,
    }
}

fn params(first: u32, count: u32, class: u32, cp_base: u32, level: u32, out_base: u32) -> Vec<u8> {
    let mut b = vec![0u8; abi::PARAMS_SIZE as usize];
    let mut put = |field: &str, x: u32| {
        let at = abi::params_offset(field) as usize;
        b[at..at + 4].copy_from_slice(&x.to_le_bytes());
    };
    // view_proj: identity (unused by the compute entries).
    put("first", first);
    put("count", count);
    put("class", class);
    put("cp_base", cp_base);
    put("level", level);
    put("out_base", out_base);
    for i in 0..4 {
        let at = abi::params_offset("view_proj") as usize + 4 * (5 * i);
        b[at..at + 4].copy_from_slice(&1.0f32.to_le_bytes());
    }
    b
}

fn bytes_u32(x: &[u32]) -> Vec<u8> {
    let mut b: Vec<u8> = x.iter().flat_map(|v| v.to_le_bytes()).collect();
    b.resize(b.len().max(4), 0);
    b
}
fn bytes_f32(x: &[f32]) -> Vec<u8> {
    let mut b: Vec<u8> = x.iter().flat_map(|v| v.to_le_bytes()).collect();
    b.resize(b.len().max(4), 0);
    b
}

struct Host {
    device: wgpu::Device,
    queue: wgpu::Queue,
}

impl Host {
    fn new() -> Host {
        let desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
        let instance = wgpu::Instance::new(desc);
        let adapter =
            pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
                .unwrap_or_else(|e| {
                    panic!("no adapter (lavapipe: scripts/test.sh installs it): {e}")
                });
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("foreign host"),
            // WebGPU's default limits: what any browser host gets.
            required_limits: wgpu::Limits::default(),
            ..Default::default()
        }))
        .unwrap_or_else(|e| panic!("device: {e}"));
        Host { device, queue }
    }

    fn buffer(&self, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
        let buf = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: None,
            size: bytes.len() as u64,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        self.queue.write_buffer(&buf, 0, bytes);
        buf
    }

    fn texture(&self, width: u32, height: u32, texels: &[u8]) -> wgpu::TextureView {
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let t = self.device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R32Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        self.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &t,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            texels,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * width),
                rows_per_image: Some(height),
            },
            size,
        );
        t.create_view(&wgpu::TextureViewDescriptor::default())
    }

    /// The explicit bind group layout of an entry from its ABI list.
    fn layout(&self, list: &[(u32, Access)]) -> wgpu::BindGroupLayout {
        let tex = [
            abi::binding_number("stencil_table"),
            abi::binding_number("displace_map"),
        ];
        let entries: Vec<wgpu::BindGroupLayoutEntry> = list
            .iter()
            .map(|&(binding, access)| wgpu::BindGroupLayoutEntry {
                binding,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: if tex.contains(&binding) {
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    }
                } else if binding == abi::binding_number("params") {
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    }
                } else {
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage {
                            read_only: access == Access::Read,
                        },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    }
                },
                count: None,
            })
            .collect();
        self.device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: None,
                entries: &entries,
            })
    }
}

/// One scheme's run: the vertex, patch and evaluation stages at `levels`,
/// compared with the CPU bit for bit.
fn run_scheme(
    host: &Host,
    out: &tessgen_codegen::Output,
    mesh_name: &str,
    scheme: &str,
    levels: &[u32],
) {
    let (m, e): &(Module, Entries) = out
        .plan
        .schemes
        .iter()
        .find(|(m, _)| m.name == scheme)
        .unwrap_or_else(|| panic!("no scheme {scheme}"));
    let konst = |n: &str| match m.consts.iter().find(|c| c.name == n).map(|c| &c.value) {
        Some(ConstValue::U32(x)) => *x,
        _ => panic!("{scheme}: no {n}"),
    };
    let rows = (konst("ROWS_PER_N"), konst("ROWS_FIXED"));
    let points: Vec<u32> = e.patches.iter().map(|p| p.control_points).collect();
    let obj = repo(&format!("tests/data/meshes/{mesh_name}.obj"));
    let (verts, faces) = read_obj(&obj);
    let inp = build_inputs(&verts, &faces, rows, &points);

    let wgsl = std::fs::read_to_string(repo(&format!("generated/wgsl/{scheme}.wgsl")))
        .unwrap_or_else(|err| panic!("{scheme}.wgsl: {err}"));
    let module = host
        .device
        .create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(scheme),
            source: wgpu::ShaderSource::Wgsl(wgsl.into()),
        });
    // The stencil texture from generated/table, uploaded as it is (its
    // size from the manifest).
    let table = std::fs::read(repo("generated/table/stencils.f32")).expect("stencils.f32");
    let manifest: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(repo("generated/table/stencils.json")).expect("stencils.json"),
    )
    .expect("manifest JSON");
    let width = manifest["texture_width"]
        .as_u64()
        .expect("manifest texture_width") as u32;
    let height = manifest["texture_height"]
        .as_u64()
        .expect("manifest texture_height") as u32;
    assert_eq!(
        table.len(),
        4 * (width * height) as usize,
        "stencils.f32 is the texture"
    );
    let table_view = host.texture(width, height, &table);
    let map_view = host.texture(1, 1, &0f32.to_le_bytes());

    use wgpu::BufferUsages as U;
    let storage = U::STORAGE;
    let mut bufs: HashMap<u32, wgpu::Buffer> = HashMap::new();
    let b = |n: &str| abi::binding_number(n);
    bufs.insert(
        b("positions"),
        host.buffer(&bytes_f32(&inp.positions), storage),
    );
    bufs.insert(b("valence"), host.buffer(&bytes_u32(&inp.valence), storage));
    bufs.insert(
        b("ring_offsets"),
        host.buffer(&bytes_u32(&inp.ring_offsets), storage),
    );
    bufs.insert(b("ring"), host.buffer(&bytes_u32(&inp.ring), storage));
    bufs.insert(
        b("vertex_out_offsets"),
        host.buffer(&bytes_u32(&inp.vertex_out_offsets), storage),
    );
    bufs.insert(
        b("vertex_out"),
        host.buffer(
            &vec![0u8; 12 * inp.vertex_out_points.max(1) as usize],
            storage,
        ),
    );
    bufs.insert(
        b("corner_vertex"),
        host.buffer(&bytes_u32(&inp.corner_vertex), storage),
    );
    bufs.insert(
        b("corner_sector"),
        host.buffer(&bytes_u32(&inp.corner_sector), storage),
    );
    // A closed untagged mesh has no crease or corner vertices (README:
    // every `vertex_sectors` range empty, `sectors` unused, each corner's
    // constants at its vertex's valence).
    bufs.insert(
        b("vertex_sectors"),
        host.buffer(&bytes_u32(&vec![0u32; inp.valence.len() + 1]), storage),
    );
    bufs.insert(b("sectors"), host.buffer(&bytes_u32(&[0u32; 4]), storage));
    let corner_valence: Vec<u32> = inp
        .corner_vertex
        .iter()
        .map(|&v| inp.valence[v as usize])
        .collect();
    bufs.insert(
        b("corner_valence"),
        host.buffer(&bytes_u32(&corner_valence), storage),
    );
    bufs.insert(
        b("control_points"),
        host.buffer(&vec![0u8; 12 * inp.control_points as usize], storage),
    );
    bufs.insert(
        b("patch_faces"),
        host.buffer(&bytes_u32(&inp.patch_faces), storage),
    );
    // Displacement off: scale 0, map 1×1 (README).
    bufs.insert(b("texcoords"), host.buffer(&[0u8; 4], storage));
    bufs.insert(b("owners"), host.buffer(&[0u8; 4], storage));
    bufs.insert(
        b("displace_info"),
        host.buffer(&bytes_f32(&[0.0, 1.0, 1.0, 0.0]), storage),
    );

    let entry = |name: &str| -> &'static EntryPoint {
        abi::wgsl_entry(name).unwrap_or_else(|| panic!("ABI has no {name}"))
    };
    let pipeline = |name: &str| {
        let list = abi::entry_bindings(&out.plan, m, e, entry(name));
        let layout = host.layout(&list);
        let pl = host
            .device
            .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: None,
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
        let p = host
            .device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: Some(&pl),
                module: &module,
                entry_point: Some(name),
                compilation_options: Default::default(),
                cache: None,
            });
        (p, layout, list)
    };
    let group = |layout: &wgpu::BindGroupLayout,
                 list: &[(u32, Access)],
                 params: &wgpu::Buffer,
                 samples: Option<&wgpu::Buffer>| {
        let entries: Vec<wgpu::BindGroupEntry> = list
            .iter()
            .map(|&(n, _)| wgpu::BindGroupEntry {
                binding: n,
                resource: if n == b("stencil_table") {
                    wgpu::BindingResource::TextureView(&table_view)
                } else if n == b("displace_map") {
                    wgpu::BindingResource::TextureView(&map_view)
                } else if n == b("params") {
                    params.as_entire_binding()
                } else if n == b("samples") {
                    samples.expect("a samples buffer").as_entire_binding()
                } else {
                    bufs.get(&n)
                        .unwrap_or_else(|| panic!("no buffer for binding {n}"))
                        .as_entire_binding()
                },
            })
            .collect();
        host.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout,
            entries: &entries,
        })
    };
    let uniform = |bytes: Vec<u8>| host.buffer(&bytes, U::UNIFORM);
    let wg = |items: u32, e: &EntryPoint| items.div_ceil(e.workgroup_size);

    // Construction: vertex stage over all vertices, patch stage per class.
    let scope = host.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let (vp, vl, vlist) = pipeline(abi::entry::VERTEX_STAGE);
    let (pp, pl, plist) = pipeline(abi::entry::PATCH_STAGE);
    let nv = inp.valence.len() as u32;
    let vparams = uniform(params(0, nv, 0, 0, 1, 0));
    let mut runs = vec![(
        &vp,
        group(&vl, &vlist, &vparams, None),
        wg(nv, entry(abi::entry::VERTEX_STAGE)),
    )];
    let pparams: Vec<_> = inp
        .classes
        .iter()
        .filter(|c| c.2 > 0)
        .map(|&(class, first, count, cp_base, _)| {
            (count, uniform(params(first, count, class, cp_base, 1, 0)))
        })
        .collect();
    for (count, p) in &pparams {
        runs.push((
            &pp,
            group(&pl, &plist, p, None),
            wg(*count, entry(abi::entry::PATCH_STAGE)),
        ));
    }
    let mut enc = host.device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        for (p, g, x) in &runs {
            pass.set_pipeline(p);
            pass.set_bind_group(0, g, &[]);
            pass.dispatch_workgroups(*x, 1, 1);
        }
    }
    host.queue.submit([enc.finish()]);

    let (ep, el, elist) = pipeline(abi::entry::EVAL);
    let mesh = Mesh::from_obj_path(&obj).unwrap_or_else(|err| panic!("{err}"));
    for &level in levels {
        let spp = (level + 1) * (level + 1);
        let faces_n = inp.patch_faces.len() as u32;
        let bytes = (faces_n * spp * abi::SAMPLE_FLOATS * 4) as u64;
        let samples = host.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("samples"),
            size: bytes,
            usage: U::STORAGE | U::COPY_SRC,
            mapped_at_creation: false,
        });
        let staging = host.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: bytes,
            usage: U::MAP_READ | U::COPY_DST,
            mapped_at_creation: false,
        });
        // One samples buffer in patch_faces order: out_base = first · spp.
        let eparams: Vec<_> = inp
            .classes
            .iter()
            .filter(|c| c.2 > 0)
            .map(|&(class, first, count, cp_base, _)| {
                (
                    count,
                    uniform(params(first, count, class, cp_base, level, first * spp)),
                )
            })
            .collect();
        let groups: Vec<_> = eparams
            .iter()
            .map(|(count, p)| {
                (
                    group(&el, &elist, p, Some(&samples)),
                    wg(count * spp, entry(abi::entry::EVAL)),
                )
            })
            .collect();
        let mut enc = host.device.create_command_encoder(&Default::default());
        {
            let mut pass = enc.begin_compute_pass(&Default::default());
            pass.set_pipeline(&ep);
            for (g, x) in &groups {
                pass.set_bind_group(0, g, &[]);
                pass.dispatch_workgroups(*x, 1, 1);
            }
        }
        enc.copy_buffer_to_buffer(&samples, 0, &staging, 0, bytes);
        host.queue.submit([enc.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        host.device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .unwrap_or_else(|err| panic!("poll: {err}"));
        rx.recv().expect("map callback").expect("map");
        let floats: Vec<f32> = staging
            .get_mapped_range(..)
            .expect("mapped")
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        staging.unmap();

        let reference = tessellate(&mesh, &Request::uniform(scheme, level))
            .ok()
            .and_then(|o| o.into_grid())
            .unwrap_or_else(|| panic!("{scheme} L{level}: CPU reference"));
        let sf = abi::SAMPLE_FLOATS as usize;
        let mut compared = 0;
        for (p, &face) in inp.patch_faces.iter().enumerate() {
            for s in 0..spp as usize {
                let g = &floats[sf * (p * spp as usize + s)..][..sf];
                let at = face as usize * spp as usize + s;
                let (cp, cn) = (reference.positions[at], reference.normals[at]);
                let want = [cp.x, cp.y, cp.z, cn.x, cn.y, cn.z];
                for k in 0..sf {
                    assert_eq!(
                        g[k].to_bits(),
                        want[k].to_bits(),
                        "{mesh_name} {scheme} level {level}: face {face} sample {s} float {k}: GPU {} CPU {}",
                        g[k],
                        want[k]
                    );
                }
                compared += 1;
            }
        }
        assert_eq!(compared, faces.len() * spp as usize);
        eprintln!("{mesh_name} {scheme} level {level}: {compared} samples equal bit for bit");
    }
    if let Some(err) = pollster::block_on(scope.pop()) {
        panic!("{scheme}: wgpu validation: {err}");
    }
}

fn compile() -> tessgen_codegen::Output {
    Builder::new()
        .builtin_schemes()
        .target(Target::Wgsl)
        .command("tessgen generate --out generated")
        .compile()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The cube (every face extraordinary) and a mixed mesh (both classes,
/// so `first`, `cp_base` and `out_base` of the second class matter), with
/// PCCM and ACC. Gregory is left out: its rational interior blend may
/// round differently on llvmpipe (tests/tests/adaptive_wgpu.rs), so it is
/// not bit-exact against the CPU on any host.
#[test]
fn meshes_from_the_readme_equal_the_cpu() {
    let out = compile();
    let host = Host::new();
    for mesh in ["catmark_cube", "catmark_righthanded"] {
        for scheme in ["pccm", "acc"] {
            run_scheme(&host, &out, mesh, scheme, &[1, 4, 7]);
        }
    }
}

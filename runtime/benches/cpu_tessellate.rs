//! `cpu_tessellate`: construction (vertex + patch stage; fresh, and per
//! deformation into the same buffers, the latter for ACC, Gregory and
//! Gregory-OSD too) and evaluation of PCCM on the largest
//! closed shared mesh (catmark_righthanded refined three times, 27,776
//! quads) at N = 9, 17 and 33, into reused buffers: the grid path, the
//! per-sample path and a plain fill of the same output (the write floor),
//! so each figure has its same-run baselines; and pn's triangle path on the
//! same quads split into triangles. Throughput is reported in
//! samples (tessellated vertices) per second. `tessgen bench` reports the
//! same with a thread count (docs/performance.md).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec3;
use tessgen_runtime::{cpu, Mesh, Topology};

fn bench(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/meshes/big/catmark_righthanded_L3.obj"
    );
    let mesh = match Mesh::from_obj_path(path) {
        Ok(m) => m,
        Err(e) => panic!("{path}: {e}"),
    };
    let topo = match Topology::build(&mesh, &cpu::topology_options()) {
        Ok(t) => t,
        Err(e) => panic!("{path}: {e}"),
    };
    let positions: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    let Ok(kernels) = cpu::scheme("pccm") else {
        panic!("pccm kernels missing")
    };
    let mut group = c.benchmark_group("cpu_tessellate");
    group.sample_size(10);
    group.throughput(Throughput::Elements(mesh.num_faces() as u64));
    group.bench_function("construct", |b| {
        b.iter(|| cpu::construct(&topo, &positions, kernels).map(|p| p.control_points.len()))
    });
    let Ok(prep) = cpu::Construction::new(&topo, kernels) else {
        panic!("pccm construction")
    };
    let mut patches = prep.construct(&positions);
    group.bench_function("construct per deformation", |b| {
        b.iter(|| prep.update(&positions, &mut patches).is_ok())
    });
    // The other quad schemes' construction per deformation (issue 17's
    // ≤ 1 ms is per scheme): their vertex stages differ in rows and terms.
    for name in ["acc", "gregory", "gregory_osd"] {
        let Ok(k) = cpu::scheme(name) else {
            panic!("{name} kernels missing")
        };
        let Ok(other) = cpu::Construction::new(&topo, k) else {
            panic!("{name} construction")
        };
        let mut out = other.construct(&positions);
        group.bench_function(format!("construct per deformation/{name}"), |b| {
            b.iter(|| other.update(&positions, &mut out).is_ok())
        });
    }
    for level in [9u32, 17, 33] {
        // Buffers allocated and first-touched once, outside the timings.
        let Ok(mut t) = cpu::evaluate(&patches, level) else {
            panic!("evaluate")
        };
        group.throughput(Throughput::Elements(t.positions.len() as u64));
        group.bench_function(format!("evaluate_into/N={level}"), |b| {
            b.iter(|| cpu::evaluate_into(&patches, level, &mut t).is_ok())
        });
        group.bench_function(format!("per-sample path/N={level}"), |b| {
            b.iter(|| {
                cpu::evaluate_per_sample_into(&patches, level, &mut t.positions, &mut t.normals)
                    .is_ok()
            })
        });
        group.bench_function(format!("fill floor/N={level}"), |b| {
            b.iter(|| {
                t.positions.fill(Vec3::ONE);
                t.normals.fill(Vec3::ONE);
            })
        });
    }
    // The triangle path: pn on the quads split into triangles (55,552
    // patches), as `tessgen bench --scheme pn` runs it.
    let (Ok(pn), Ok(tri)) = (cpu::scheme("pn"), cpu::tri_mesh(&mesh, true, None)) else {
        panic!("pn kernels or the split mesh")
    };
    let Ok(tri_patches) = cpu::construct_tri(&tri, pn) else {
        panic!("pn construction")
    };
    for level in [9u32, 17, 33] {
        let Ok(mut t) = cpu::evaluate(&tri_patches, level) else {
            panic!("evaluate pn")
        };
        group.throughput(Throughput::Elements(t.positions.len() as u64));
        group.bench_function(format!("pn evaluate_into/N={level}"), |b| {
            b.iter(|| cpu::evaluate_into(&tri_patches, level, &mut t).is_ok())
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

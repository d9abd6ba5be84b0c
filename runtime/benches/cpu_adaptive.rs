//! `cpu_adaptive`: the CPU adaptive path (power-of-two edge levels, patches
//! bucketed by their largest edge level, snapped transitions; the generated
//! Rust the WGSL instanced path also runs) against uniform evaluation at the
//! adaptive path's largest level, in the same run, on catmark_righthanded
//! refined three times (27,776 quads). Throughput is in samples per second,
//! so the ratio of the two rows is the cost of adaptivity per sample; the
//! sample counts themselves differ (adaptive evaluates fewer).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::Vec3;
use tessgen_runtime::adaptive::{self, Adaptive, Metric, Partitioning};
use tessgen_runtime::{cpu, Mesh, Topology};

const MAX_LEVEL: u32 = 16;

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
    let patches = match cpu::construct(&topo, &positions, kernels) {
        Ok(p) => p,
        Err(e) => panic!("{path}: {e}"),
    };
    let (_, edges) = adaptive::edge_ids(&topo);
    let random = Adaptive {
        metric: Metric::Buffer(adaptive::random_factors(edges, 0x7e55_6e11, 1.0, 16.0)),
        partitioning: Partitioning::Integer,
        min: 1.0,
        max: MAX_LEVEL as f32,
    };
    let adaptive_samples =
        match adaptive::evaluate_cpu_adaptive(&patches, &topo, &random, MAX_LEVEL) {
            Ok(t) => t.positions.len() as u64,
            Err(e) => panic!("{path}: {e}"),
        };
    let mut group = c.benchmark_group("cpu_adaptive");
    group.sample_size(10);
    let uniform = mesh.num_faces() as u64 * ((MAX_LEVEL + 1) * (MAX_LEVEL + 1)) as u64;
    group.throughput(Throughput::Elements(uniform));
    group.bench_function(format!("uniform/N={MAX_LEVEL}"), |b| {
        b.iter(|| cpu::evaluate(&patches, MAX_LEVEL).map(|t| t.positions.len()))
    });
    group.throughput(Throughput::Elements(adaptive_samples));
    group.bench_function(format!("adaptive/random[1,16]/max={MAX_LEVEL}"), |b| {
        b.iter(|| {
            adaptive::evaluate_cpu_adaptive(&patches, &topo, &random, MAX_LEVEL)
                .map(|t| t.positions.len())
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

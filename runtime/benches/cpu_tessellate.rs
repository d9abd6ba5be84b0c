//! `cpu_tessellate`: construction (vertex + patch stage) and evaluation of
//! PCCM on the largest closed shared mesh (catmark_righthanded refined three
//! times, 27,776 quads) at N = 9 and N = 33. Throughput is reported in
//! samples (tessellated vertices) per second.

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
    for level in [9u32, 33] {
        let samples = mesh.num_faces() as u64 * ((level + 1) * (level + 1)) as u64;
        group.throughput(Throughput::Elements(samples));
        group.bench_function(format!("construct+evaluate/N={level}"), |b| {
            b.iter(|| {
                let p = cpu::construct(&topo, &positions, kernels).ok()?;
                cpu::evaluate(&p, level).ok().map(|t| t.positions.len())
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

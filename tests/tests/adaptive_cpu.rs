//! CPU adaptive tessellation (`runtime::adaptive::evaluate_cpu`): random
//! per-edge factors snapped to power-of-two edge levels, patches bucketed
//! by their largest edge level, boundary samples snapped onto the edges'
//! own coarser points. The exact weld of every quad scheme on the closed
//! shared meshes is closed (degenerate transition triangles skipped); the
//! negative control — each patch a plain grid at its bucket level, no
//! snapping — has T-junctions and opens.

mod common;

use glam::Vec3;
use tessgen_runtime::adaptive::{self, AdaptiveTessellation};
use tessgen_runtime::{cpu, weld, Topology};

const SEED: u64 = 0x7e55_6e11;

fn setup(scheme: &str, name: &str) -> Option<(Topology, cpu::Patches)> {
    let mesh = common::mesh(name);
    let topo = Topology::build(&mesh, &cpu::topology_options()).expect("topology");
    let positions: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| Vec3::from_array(*p))
        .collect();
    let kernels = cpu::scheme(scheme).expect("scheme");
    let patches = cpu::construct(&topo, &positions, kernels).ok()?;
    Some((topo, patches))
}

fn weld_soup(t: &AdaptiveTessellation) -> weld::WeldReport {
    let soup: Vec<Vec3> = t.triangles().into_iter().flatten().collect();
    weld::weld_triangles(&soup, 3, &[[0, 1, 2]])
}

#[test]
fn random_edge_factors_weld_closed_on_the_cpu() {
    let mut bad = Vec::new();
    for scheme in ["regular", "pccm", "acc", "gregory", "gregory_osd"] {
        for name in ["catmark_cube", "catmark_torus", "catmark_toroidal_tet"] {
            let Some((topo, patches)) = setup(scheme, name) else {
                continue;
            };
            let (_, edges) = adaptive::edge_ids(&topo);
            let factors = adaptive::random_factors(edges, SEED, 1.0, 24.0);
            let t = adaptive::evaluate_cpu(&patches, &topo, &factors, 64).expect("adaptive");
            assert!(t.positions.iter().all(|p| p.is_finite()));
            let r = weld_soup(&t);
            let buckets: Vec<String> = t
                .buckets()
                .iter()
                .map(|(l, f)| format!("{l}:{}", f.len()))
                .collect();
            println!(
                "| {scheme} | cpu | {name} | buckets {} | {} triangles ({} degenerate) | {} open |",
                buckets.join(" "),
                r.triangles,
                r.degenerate_triangles,
                r.open_edges
            );
            // Edges of different levels meet at patches: the snapped
            // transitions are really exercised.
            let mut distinct = t.edge_levels.clone();
            distinct.sort_unstable();
            distinct.dedup();
            assert!(
                distinct.len() > 2,
                "{scheme} {name}: edge levels {distinct:?}"
            );
            if r.open_edges != 0 || r.overused_edges != 0 {
                bad.push(format!("{scheme} {name}: {r:?}"));
            }
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// Negative control: the same per-patch bucket levels without snapping
/// (each patch a plain grid at its own level) leave T-junctions.
#[test]
fn per_patch_levels_without_snapping_open_the_weld() {
    let (topo, patches) = setup("pccm", "catmark_toroidal_tet").expect("pccm");
    let (_, edges) = adaptive::edge_ids(&topo);
    let factors = adaptive::random_factors(edges, SEED, 1.0, 24.0);
    let t = adaptive::evaluate_cpu(&patches, &topo, &factors, 64).expect("adaptive");
    let k = patches.scheme;
    let mut soup = Vec::new();
    for (f, &l) in t.levels.iter().enumerate() {
        let cp = &patches.control_points
            [patches.cp_offsets[f] as usize..patches.cp_offsets[f + 1] as usize];
        let at = |s: u32| (k.eval)(cp, patches.face_class[f], 0, s % (l + 1), s / (l + 1), l);
        for tri in tessgen_runtime::grid::grid_triangles(l) {
            soup.extend(tri.map(|s| at(s).position));
        }
    }
    let r = weld::weld_triangles(&soup, 3, &[[0, 1, 2]]);
    println!(
        "| pccm | cpu | catmark_toroidal_tet | no snapping (negative control) | {} open |",
        r.open_edges
    );
    assert!(r.open_edges > 0, "unsnapped per-patch levels stayed closed");
}

use super::*;
use crate::mesh::features::BoundaryRule;

fn data(name: &str) -> Mesh {
    let path = format!("{}/../tests/data/meshes/{name}", env!("CARGO_MANIFEST_DIR"));
    Mesh::from_obj_path(path).expect("test mesh")
}

fn cube() -> Mesh {
    let p = vec![
        [-1.0, -1.0, -1.0],
        [1.0, -1.0, -1.0],
        [1.0, 1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, -1.0, 1.0],
        [1.0, -1.0, 1.0],
        [1.0, 1.0, 1.0],
        [-1.0, 1.0, 1.0],
    ];
    let f = vec![
        vec![0, 3, 2, 1],
        vec![4, 5, 6, 7],
        vec![0, 1, 5, 4],
        vec![1, 2, 6, 5],
        vec![2, 3, 7, 6],
        vec![3, 0, 4, 7],
    ];
    Mesh::from_raw(p, &f).expect("cube")
}

fn row_sum(t: &StencilTable, r: usize) -> f64 {
    t.row(r).map(|(_, w)| w as f64).sum()
}

#[test]
fn cube_vertex_point_is_the_catmull_clark_rule() {
    let r = refine(&cube(), &Features::new(), 1, 32).expect("refine");
    // Valence 3 corner at ±1: (n-2)/n·V + Σ neighbours/n² + Σ face points/n².
    // Neighbours sum to (1,1,1)·(-1)… for V = (-1,-1,-1): each neighbour has one
    // coordinate flipped; the face points are the face centres.
    let v = r.mesh.positions[0];
    let n = 3.0f64;
    // V·(n−2)/n + (neighbour x sum −1)/9 + (face-point x sum −1)/9 = −5/9.
    let expect = -((n - 2.0) / n) - 1.0 / 9.0 - 1.0 / 9.0;
    for c in v {
        assert!((c as f64 - expect).abs() < 1e-6, "{v:?} vs {expect}");
    }
    assert_eq!(r.mesh.num_faces(), 24);
    assert_eq!(r.mesh.num_vertices(), 8 + 6 + 12);
    for k in 0..r.stencils.rows() {
        assert!((row_sum(&r.stencils, k) - 1.0).abs() < 1e-6, "row {k}");
    }
    assert_eq!(r.blocks.len(), 6);
    assert!(r.blocks.iter().all(|b| b.corner.is_none() && b.depth == 1));
}

#[test]
fn quad_children_keep_the_parent_parameterization() {
    // One flat quad: child (x, y) must start at base (x/2, y/2) and keep u, v.
    let m = Mesh::from_raw(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        &[vec![0, 1, 2, 3]],
    )
    .expect("quad");
    let r = refine(
        &m,
        &Features::new().with_boundary(BoundaryRule::EdgeAndCorner),
        2,
        32,
    )
    .expect("refine");
    assert_eq!(r.leaves.len(), 16);
    for (f, leaf) in r.leaves.iter().enumerate() {
        let face = r.mesh.face(f);
        let p0 = r.mesh.positions[face[0] as usize];
        let p1 = r.mesh.positions[face[1] as usize];
        let p3 = r.mesh.positions[face[3] as usize];
        // Corners of a flat, sharp-bounded square refine to their affine
        // positions, so the leaf's first corner sits at (x, y)/4.
        assert!(
            (p0[0] - leaf.x as f32 / 4.0).abs() < 1e-6,
            "leaf {leaf:?} at {p0:?}"
        );
        assert!(
            (p0[1] - leaf.y as f32 / 4.0).abs() < 1e-6,
            "leaf {leaf:?} at {p0:?}"
        );
        assert!(p1[0] > p0[0] && (p1[1] - p0[1]).abs() < 1e-6, "u along +x");
        assert!(p3[1] > p0[1] && (p3[0] - p0[0]).abs() < 1e-6, "v along +y");
    }
}

#[test]
fn nonquads_become_quads_with_one_block_per_sub_face() {
    let m = data("catmark_nonquads.obj");
    let (features, _) = Features::from_mesh(&m).expect("tags");
    let need = need(&m, &features);
    assert_eq!(need.non_quads, 10);
    assert_eq!(need.levels(), 1);
    let r = refine(&m, &features, 1, 32).expect("refine");
    assert!((0..r.mesh.num_faces()).all(|f| r.mesh.face(f).len() == 4));
    let quads = (0..m.num_faces()).filter(|&f| m.face(f).len() == 4).count();
    let sub: usize = (0..m.num_faces())
        .filter(|&f| m.face(f).len() != 4)
        .map(|f| m.face(f).len())
        .sum();
    assert_eq!(r.blocks.len(), quads + sub);
    // Blocks are in base face order, sub-faces by corner.
    for w in r.blocks.windows(2) {
        assert!((w[0].face, w[0].corner) < (w[1].face, w[1].corner));
    }
    // The refined mesh builds as an all-quad topology.
    Topology::build_with(&r.mesh, &TopologyOptions::default(), &r.features).expect("topology");
    for k in 0..r.stencils.rows() {
        assert!((row_sum(&r.stencils, k) - 1.0).abs() < 1e-6, "row {k}");
    }
}

#[test]
fn semi_sharp_creases_lose_one_per_step() {
    let m = cube();
    let f = Features::new()
        .with_crease(0, 1, 2.5)
        .with_crease(1, 2, 10.0)
        .with_corner(6, 0.5);
    let n = need(&m, &f);
    assert_eq!(n.crease_levels(), 3);
    let r1 = refine(&m, &f, 1, 32).expect("refine");
    let mut values: Vec<f32> = r1.features.edge_sharpness.values().copied().collect();
    values.sort_by(f32::total_cmp);
    assert_eq!(values, vec![1.5, 1.5, 10.0, 10.0]);
    assert!(r1.features.vertex_sharpness.is_empty());
    let r3 = refine(&m, &f, 3, 32).expect("refine");
    assert!(r3.features.edge_sharpness.values().all(|&s| s == 10.0));
    assert_eq!(r3.features.edge_sharpness.len(), 8);
}

#[test]
fn fractional_edge_point_blends_sharp_and_smooth() {
    let m = cube();
    let smooth = refine(&m, &Features::new(), 1, 32).expect("refine");
    let sharp = refine(&m, &Features::new().with_crease(0, 1, 1.0), 1, 32).expect("refine");
    let half = refine(&m, &Features::new().with_crease(0, 1, 0.5), 1, 32).expect("refine");
    // Edge (0, 1) is the first edge of face 0's corner 3 → find it by position.
    let mid = [0.0f32, -1.0, -1.0];
    let e = (0..sharp.mesh.num_vertices())
        .find(|&v| sharp.mesh.positions[v] == mid)
        .expect("sharp edge point at the midpoint");
    for c in 0..3 {
        let expect = 0.5 * (smooth.mesh.positions[e][c] + sharp.mesh.positions[e][c]);
        assert!((half.mesh.positions[e][c] - expect).abs() < 1e-6);
    }
}

#[test]
fn holes_and_texcoords_follow_the_children() {
    let m = data("catmark_cube_uv.obj");
    let f = Features::new().with_hole(2);
    let r = refine(&m, &f, 1, 32).expect("refine");
    let holes: Vec<u32> = r.features.holes.iter().copied().collect();
    assert_eq!(holes, vec![8, 9, 10, 11]);
    assert_eq!(r.mesh.face_texcoords.len(), r.mesh.face_vertices.len());
    // The first corner of child 0 of face 0 keeps the base corner's uv.
    assert_eq!(r.mesh.corner_texcoord(0), m.corner_texcoord(0));
}

#[test]
fn bad_base_meshes_are_refused_before_refining() {
    // Three faces on one edge.
    let m = Mesh::from_raw(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        &[vec![0, 1, 2], vec![1, 0, 3], vec![0, 1, 4]],
    )
    .expect("mesh");
    assert!(matches!(
        refine(&m, &Features::new(), 1, 32),
        Err(TopologyError::NonManifoldEdge { .. })
    ));
}

/// single_crease with its tags: sharpness up to 5.7 needs 6 steps.
fn single_crease() -> (Mesh, Features) {
    let m = data("catmark_single_crease.obj");
    let (f, _) = Features::from_mesh(&m).expect("tags");
    (m, f)
}

#[test]
fn adaptive_depths_cover_every_block_once() {
    let (m, f) = single_crease();
    let parts = refine_adaptive(
        &m,
        &f,
        Depths {
            features: 6,
            isolate: 0,
        },
        8,
        32,
    )
    .expect("refine");
    let depths: Vec<u32> = parts.iter().map(|p| p.levels).collect();
    assert_eq!(depths, vec![0, 1, 2, 3, 4, 5, 6], "one part per depth");
    let blocks = &parts[0].blocks;
    assert_eq!(blocks.len(), m.num_faces());
    assert!(parts.iter().all(|p| &p.blocks == blocks), "shared blocks");
    // Every block's area, at the finest depth's resolution, is covered by
    // exactly one emitting leaf (a face that is not a hole) over all depths.
    let fine = 1u32 << 6;
    let mut cover = vec![0u8; blocks.len() * (fine * fine) as usize];
    let mut deepest = vec![0u32; blocks.len()];
    for p in &parts {
        for (face, l) in p.leaves.iter().enumerate() {
            if p.features.holes.contains(&(face as u32)) {
                continue;
            }
            let b = l.block as usize;
            deepest[b] = deepest[b].max(p.levels);
            let side = fine >> p.levels;
            for y in l.y * side..(l.y + 1) * side {
                for x in l.x * side..(l.x + 1) * side {
                    cover[b * (fine * fine) as usize + (y * fine + x) as usize] += 1;
                }
            }
        }
    }
    assert!(cover.iter().all(|&c| c == 1), "every cell once");
    for (b, block) in blocks.iter().enumerate() {
        assert_eq!(block.depth, deepest[b], "block {b}");
    }
    // Faces far from a semi-sharp edge stay whole; the refined band is a
    // small part of what uniform refinement would evaluate.
    assert!(blocks.iter().any(|b| b.depth == 0));
    let evaluated: usize = parts.iter().map(|p| p.mesh.num_faces()).sum();
    assert!(
        evaluated < m.num_faces() * 4usize.pow(6) / 20,
        "{evaluated}"
    );
}

#[test]
fn adaptive_vertices_are_the_uniform_refinement_vertices() {
    let (m, f) = single_crease();
    let parts = refine_adaptive(
        &m,
        &f,
        Depths {
            features: 3,
            isolate: 0,
        },
        8,
        32,
    )
    .expect("refine");
    for p in &parts {
        for r in 0..p.mesh.num_vertices() {
            assert!((row_sum(&p.stencils, r) - 1.0).abs() < 1e-6, "row {r}");
        }
        let uniform = refine(&m, &f, p.levels, 32).expect("uniform");
        // The same points, each from a stencil composed in the same order.
        let mut at: std::collections::HashMap<[u32; 3], usize> = Default::default();
        for (v, q) in uniform.mesh.positions.iter().enumerate() {
            at.insert(q.map(f32::to_bits), v);
        }
        for (v, q) in p.mesh.positions.iter().enumerate() {
            let u = at.get(&q.map(f32::to_bits));
            assert!(u.is_some(), "depth {}: vertex {v} {q:?}", p.levels);
        }
        // Sharpness left on the kept edges is the uniform one.
        let mut left: Vec<f32> = p.features.edge_sharpness.values().copied().collect();
        left.sort_by(f32::total_cmp);
        left.dedup();
        let mut want: Vec<f32> = uniform.features.edge_sharpness.values().copied().collect();
        want.sort_by(f32::total_cmp);
        want.dedup();
        assert!(left.iter().all(|s| want.contains(s)), "depth {}", p.levels);
    }
}

#[test]
fn adaptive_without_features_is_one_part() {
    let m = cube();
    let parts = refine_adaptive(
        &m,
        &Features::new(),
        Depths {
            features: 6,
            isolate: 0,
        },
        8,
        32,
    )
    .expect("refine");
    assert_eq!(parts.len(), 1);
    assert_eq!(parts[0].levels, 0);
    assert_eq!(parts[0].mesh.num_faces(), 6);
    // A semi-sharp edge: the faces on both sides are refined, not the rest.
    let f = Features::new().with_crease(0, 1, 1.5);
    let parts = refine_adaptive(
        &m,
        &f,
        Depths {
            features: 6,
            isolate: 0,
        },
        8,
        32,
    )
    .expect("refine");
    assert_eq!(parts.iter().map(|p| p.levels).max(), Some(2));
    let whole = parts[0].blocks.iter().filter(|b| b.depth == 0).count();
    assert!(whole > 0 && whole < 6, "{whole} whole faces");
}

#[test]
fn isolation_refines_around_extraordinary_vertices_only() {
    // Every child of a cube face has a valence-3 corner, so depth 1 has no
    // leaves; from depth 2 on, 3 of the 4 children of a refined face are
    // regular leaves and the corner child is refined again.
    let m = cube();
    let d = Depths {
        features: 0,
        isolate: 3,
    };
    let parts = refine_adaptive(&m, &Features::new(), d, 8, 32).expect("refine");
    assert_eq!(parts.iter().map(|p| p.levels).collect::<Vec<_>>(), [2, 3]);
    assert!(parts[0].blocks.iter().all(|b| b.depth == 3));
    let leaves = |p: &Refinement| p.mesh.num_faces() - p.features.holes.len();
    assert_eq!(
        (leaves(&parts[0]), leaves(&parts[1])),
        (6 * 4 * 3, 6 * 4 * 4)
    );
    let d = Depths {
        features: 0,
        isolate: 2,
    };
    // righthanded: faces far from its extraordinary vertices stay whole.
    let (x, f) = {
        let m = data("catmark_righthanded.obj");
        let (f, _) = Features::from_mesh(&m).expect("tags");
        (m, f)
    };
    let parts = refine_adaptive(&x, &f, d, 8, 32).expect("refine");
    let whole = parts[0].blocks.iter().filter(|b| b.depth == 0).count();
    assert!(
        whole > 0 && whole < x.num_faces(),
        "{whole} of {}",
        x.num_faces()
    );
}

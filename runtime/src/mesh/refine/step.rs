//! One Catmull-Clark step with OpenSubdiv's Sdc rules: smooth, dart,
//! crease and corner vertices, boundaries as infinitely sharp edges, the
//! uniform crease rule (a child edge has sharpness `s − 1`), and the
//! fractional blend where a vertex's rule changes between parent and child.
//!
//! Child numbering, fixed so refinement is reproducible:
//! vertices `[vertex points (same index as the parent) | face points (per
//! face) | edge points (per edge, in order of first use by the faces)]`;
//! faces: the children of parent face `f` are `face_offsets[f] + i`, one per
//! corner `i`, so a child face id is its parent's corner (half-edge) id.
//!
//! Sub-face orientation (docs/boundaries.md §8): a quad's four children keep
//! the parent's `(u, v)` directions — child `i` covers the quadrant
//! [`QUAD_CHILD_OFFSET`]`[i]` of `[0,1]²` at half scale — so a base quad's
//! `(u, v)` grid can be read off its children. An n-gon's child `i` is
//! `(vᵢ, e(i,i+1), F, e(i−1,i))`: `u` runs from corner `i` along the next
//! edge, `v` along the previous one, as OpenSubdiv's sub-faces do.

use std::collections::HashMap;

use crate::mesh::features::SHARPNESS_INFINITE;

/// Offset `(x, y)` in half units of child `i` of a quad.
pub const QUAD_CHILD_OFFSET: [(u32, u32); 4] = [(0, 0), (1, 0), (1, 1), (0, 1)];

/// Child `i` of an `n`-gon from its corner `v`, the next and previous edge
/// points and the face point, in the order of the module docs (generic so
/// face-varying data follows the same corners).
pub(super) fn child_face<T>(n: usize, i: usize, v: T, next: T, face: T, prev: T) -> [T; 4] {
    if n == 4 {
        match i {
            0 => [v, next, face, prev],
            1 => [prev, v, next, face],
            2 => [face, prev, v, next],
            _ => [next, face, prev, v],
        }
    } else {
        [v, next, face, prev]
    }
}

/// A polygon mesh with the features one step needs.
#[derive(Debug, Clone, Default)]
pub(super) struct Level {
    pub num_vertices: usize,
    pub face_offsets: Vec<u32>,
    pub face_vertices: Vec<u32>,
    /// Sharpness of tagged edges, keyed `(min, max)`.
    pub edge_sharpness: HashMap<(u32, u32), f32>,
    /// Sharpness of tagged vertices.
    pub vertex_sharpness: HashMap<u32, f32>,
    /// Valence-2 boundary vertices are corners (edge-and-corner rule).
    pub boundary_corners: bool,
}

impl Level {
    pub fn num_faces(&self) -> usize {
        self.face_offsets.len() - 1
    }

    pub fn face(&self, f: usize) -> &[u32] {
        &self.face_vertices[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }
}

/// The child level and its vertices as rows over the parent's vertices.
pub(super) struct Step {
    pub child: Level,
    pub rows: Vec<Vec<(u32, f64)>>,
}

/// The vertex rules of Sdc, ordered by sharpness.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Rule {
    Smooth,
    Crease,
    Corner,
}

/// Sharpness of a child edge or vertex under the uniform rule.
fn child_sharpness(s: f32) -> f32 {
    if s >= SHARPNESS_INFINITE {
        SHARPNESS_INFINITE
    } else {
        (s - 1.0).max(0.0)
    }
}

fn rule(vertex_sharpness: f32, sharp_edges: usize) -> Rule {
    if vertex_sharpness > 0.0 || sharp_edges > 2 {
        Rule::Corner
    } else if sharp_edges == 2 {
        Rule::Crease
    } else {
        Rule::Smooth
    }
}

/// Adds `w · row` into `acc` (unsorted; merged by [`finish`]).
fn add(acc: &mut Vec<(u32, f64)>, row: &[(u32, f64)], w: f64) {
    acc.extend(row.iter().map(|&(i, x)| (i, x * w)));
}

/// Sorts a row by vertex and merges duplicates.
fn finish(mut row: Vec<(u32, f64)>) -> Vec<(u32, f64)> {
    row.sort_by_key(|&(i, _)| i);
    let mut out: Vec<(u32, f64)> = Vec::with_capacity(row.len());
    for (i, w) in row {
        match out.last_mut() {
            Some((j, x)) if *j == i => *x += w,
            _ => out.push((i, w)),
        }
    }
    out.retain(|&(_, w)| w != 0.0);
    out
}

/// One refinement step of `level` (a manifold, consistently oriented
/// polygon mesh: [`crate::mesh::topology::Topology`] checked it).
pub(super) fn step(level: &Level) -> Step {
    let nv = level.num_vertices;
    let nf = level.num_faces();
    // Edges in order of first use; faces of each edge (1 or 2).
    let mut edge_id: HashMap<(u32, u32), u32> = HashMap::with_capacity(level.face_vertices.len());
    let mut edges: Vec<(u32, u32)> = Vec::new();
    let mut edge_faces: Vec<Vec<u32>> = Vec::new();
    let mut corner_edge = vec![0u32; level.face_vertices.len()];
    for f in 0..nf {
        let face = level.face(f);
        let first = level.face_offsets[f] as usize;
        for (i, &a) in face.iter().enumerate() {
            let b = face[(i + 1) % face.len()];
            let key = (a.min(b), a.max(b));
            let e = *edge_id.entry(key).or_insert_with(|| {
                edges.push(key);
                edge_faces.push(Vec::new());
                (edges.len() - 1) as u32
            });
            edge_faces[e as usize].push(f as u32);
            corner_edge[first + i] = e;
        }
    }
    let ne = edges.len();
    let boundary = |e: usize| edge_faces[e].len() < 2;
    let sharpness = |e: usize| -> f32 {
        if boundary(e) {
            SHARPNESS_INFINITE
        } else {
            level.edge_sharpness.get(&edges[e]).copied().unwrap_or(0.0)
        }
    };
    // Incident edges and faces per vertex.
    let mut vertex_edges: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for (e, &(a, b)) in edges.iter().enumerate() {
        vertex_edges[a as usize].push(e as u32);
        vertex_edges[b as usize].push(e as u32);
    }
    let mut vertex_faces: Vec<Vec<u32>> = vec![Vec::new(); nv];
    for f in 0..nf {
        for &v in level.face(f) {
            vertex_faces[v as usize].push(f as u32);
        }
    }

    let face_point = |f: usize| -> Vec<(u32, f64)> {
        let face = level.face(f);
        let w = 1.0 / face.len() as f64;
        face.iter().map(|&v| (v, w)).collect()
    };
    let face_points: Vec<Vec<(u32, f64)>> = (0..nf).map(face_point).collect();

    let mut rows: Vec<Vec<(u32, f64)>> = Vec::with_capacity(nv + nf + ne);
    // Vertex points.
    for v in 0..nv {
        let incident = &vertex_edges[v];
        if incident.is_empty() {
            rows.push(vec![(v as u32, 1.0)]);
            continue;
        }
        let mut vs = level
            .vertex_sharpness
            .get(&(v as u32))
            .copied()
            .unwrap_or(0.0);
        let on_boundary = incident.iter().any(|&e| boundary(e as usize));
        if level.boundary_corners && on_boundary && vertex_faces[v].len() == 1 {
            vs = SHARPNESS_INFINITE;
        }
        let parent_sharp: Vec<f32> = incident.iter().map(|&e| sharpness(e as usize)).collect();
        let child_sharp: Vec<f32> = parent_sharp.iter().map(|&s| child_sharpness(s)).collect();
        let count = |s: &[f32]| s.iter().filter(|&&x| x > 0.0).count();
        let parent_rule = rule(vs, count(&parent_sharp));
        let child_rule = rule(child_sharpness(vs), count(&child_sharp));
        let other = |e: u32| {
            let (a, b) = edges[e as usize];
            if a as usize == v {
                b
            } else {
                a
            }
        };
        let mask = |r: Rule, sharp: &[f32]| -> Vec<(u32, f64)> {
            match r {
                Rule::Corner => vec![(v as u32, 1.0)],
                Rule::Crease => {
                    let mut m = vec![(v as u32, 0.75)];
                    for (k, &e) in incident.iter().enumerate() {
                        if sharp[k] > 0.0 {
                            m.push((other(e), 0.125));
                        }
                    }
                    m
                }
                Rule::Smooth => {
                    let n = incident.len() as f64;
                    let mut m = vec![(v as u32, (n - 2.0) / n)];
                    for &e in incident {
                        m.push((other(e), 1.0 / (n * n)));
                    }
                    for &f in &vertex_faces[v] {
                        add(&mut m, &face_points[f as usize], 1.0 / (n * n));
                    }
                    m
                }
            }
        };
        let row = if parent_rule == child_rule || parent_rule == Rule::Smooth {
            mask(parent_rule, &parent_sharp)
        } else {
            // Sdc's fractional weight: the mean sharpness of what transitions.
            let (mut n, mut sum) = (0usize, 0.0f32);
            if vs > 0.0 && child_sharpness(vs) <= 0.0 {
                n += 1;
                sum += vs;
            }
            for (p, c) in parent_sharp.iter().zip(&child_sharp) {
                if *p > 0.0 && *c <= 0.0 {
                    n += 1;
                    sum += p;
                }
            }
            let w = if n == 0 {
                0.0
            } else {
                (sum / n as f32).clamp(0.0, 1.0) as f64
            };
            let mut m = Vec::new();
            add(&mut m, &mask(parent_rule, &parent_sharp), w);
            add(&mut m, &mask(child_rule, &child_sharp), 1.0 - w);
            m
        };
        rows.push(finish(row));
    }
    rows.extend(face_points.iter().cloned());
    // Edge points.
    for e in 0..ne {
        let (a, b) = edges[e];
        let s = sharpness(e);
        let sharp = vec![(a, 0.5), (b, 0.5)];
        let row = if s >= 1.0 {
            sharp
        } else {
            let mut smooth = vec![(a, 0.25), (b, 0.25)];
            for &f in &edge_faces[e] {
                add(&mut smooth, &face_points[f as usize], 0.25);
            }
            if s <= 0.0 {
                smooth
            } else {
                let mut m = Vec::new();
                add(&mut m, &sharp, s as f64);
                add(&mut m, &smooth, 1.0 - s as f64);
                m
            }
        };
        rows.push(finish(row));
    }

    // Child faces and features.
    let fp = |f: usize| (nv + f) as u32;
    let ep = |e: u32| (nv + nf) as u32 + e;
    let mut child = Level {
        num_vertices: nv + nf + ne,
        face_offsets: Vec::with_capacity(level.face_vertices.len() + 1),
        face_vertices: Vec::with_capacity(4 * level.face_vertices.len()),
        boundary_corners: level.boundary_corners,
        ..Level::default()
    };
    child.face_offsets.push(0);
    for f in 0..nf {
        let face = level.face(f);
        let n = face.len();
        let first = level.face_offsets[f] as usize;
        for i in 0..n {
            let next = ep(corner_edge[first + i]);
            let prev = ep(corner_edge[first + (i + n - 1) % n]);
            child
                .face_vertices
                .extend_from_slice(&child_face(n, i, face[i], next, fp(f), prev));
            child.face_offsets.push(child.face_vertices.len() as u32);
        }
    }
    for (e, &(a, b)) in edges.iter().enumerate() {
        let s = child_sharpness(level.edge_sharpness.get(&(a, b)).copied().unwrap_or(0.0));
        if s > 0.0 {
            let m = ep(e as u32);
            child.edge_sharpness.insert((a.min(m), a.max(m)), s);
            child.edge_sharpness.insert((b.min(m), b.max(m)), s);
        }
    }
    for (&v, &s) in &level.vertex_sharpness {
        let s = child_sharpness(s);
        if s > 0.0 {
            child.vertex_sharpness.insert(v, s);
        }
    }
    Step { child, rows }
}

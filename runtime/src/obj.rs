//! OBJ output of tessellated grids — the same layout from every backend.
//!
//! Per base face, in input order: `g patch_<face>`, then `(N+1)²` `v` lines
//! and `(N+1)²` `vn` lines, row-major `j·(N+1) + i` for `u = i/N`, `v = j/N`,
//! then the grid's triangles `f a//a b//b c//c`. Coordinates use Rust's
//! shortest round-trip formatting, so equal f32 values print identical text.

use crate::cpu::Tessellation;
use crate::weld::grid_triangles;
use std::fmt::Write;

/// Render a tessellation as OBJ text.
pub fn to_obj(t: &Tessellation) -> String {
    let per = t.grid_len();
    let tris = grid_triangles(t.level);
    let mut s = String::with_capacity(t.positions.len() * 64);
    let _ = writeln!(
        s,
        "# tessgen {} level {}",
        env!("CARGO_PKG_VERSION"),
        t.level
    );
    for f in 0..t.faces {
        let _ = writeln!(s, "g patch_{f}");
        for p in &t.positions[f * per..(f + 1) * per] {
            let _ = writeln!(s, "v {} {} {}", p.x, p.y, p.z);
        }
        for n in &t.normals[f * per..(f + 1) * per] {
            let _ = writeln!(s, "vn {} {} {}", n.x, n.y, n.z);
        }
        let base = (f * per) as u32 + 1;
        for tri in &tris {
            let [a, b, c] = tri.map(|k| k + base);
            let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
        }
    }
    s
}

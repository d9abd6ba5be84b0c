//! The vertex stage: one function summing every vertex-stage output over the ring slots in
//! ring order with the f32 table weights (DESIGN.md Rule 1). A crease or corner vertex sums,
//! per sector, the sector rows over its partial ring instead (docs/boundaries.md §4).

use super::*;

/// Constants of the sector path, declared in the scheme module.
pub(crate) struct SectorConsts {
    /// `SECTOR_ROW_BASE[kind · SECTOR_MAX_FACES + m − 1]`.
    pub row_base: usize,
    /// `SECTOR_COLUMN`: first table column of the sector region.
    pub column: usize,
    /// `SECTOR_MAX_FACES`.
    pub max_faces: usize,
}

/// `acc = Σ_k w(row, col0 + k) · positions[ring[ring_base + k]]` for `k < slots`, zero
/// weights skipped: the one summation every vertex-stage value goes through.
fn sum_row(
    acc: LocalId,
    k: LocalId,
    w: LocalId,
    row: Expr,
    col0: Option<Expr>,
    ring_base: LocalId,
    slots: LocalId,
) -> Vec<Stmt> {
    let col = match col0 {
        Some(c) => add(c, l(k)),
        None => l(k),
    };
    vec![
        Stmt::Var(
            acc,
            Expr::Call(Builtin::Vec3, vec![f32c(0.0), f32c(0.0), f32c(0.0)]),
        ),
        Stmt::For(
            k,
            u(0),
            l(slots),
            vec![
                Stmt::Let(w, Expr::TableWeight(Box::new(row), Box::new(col))),
                Stmt::If(
                    bin(BinOp::Ne, l(w), f32c(0.0)),
                    vec![Stmt::Assign(
                        acc,
                        add(
                            l(acc),
                            mul(
                                fetch(
                                    Resource::Positions,
                                    fetch(Resource::Ring, add(l(ring_base), l(k))),
                                ),
                                l(w),
                            ),
                        ),
                    )],
                    vec![],
                ),
            ],
        ),
    ]
}

pub(crate) fn vertex_stage_fn(
    s: &Scheme,
    row_base: usize,
    sector: &SectorConsts,
    ra: u32,
    rb: u32,
) -> Function {
    let mut f = Function::new(
        "vertex_stage",
        format!(
            "Vertex stage of `{}`: every output row of this vertex's valence, each the sum over \
             ring slots 0..2n in ring order (stored once per vertex, canonical start) of \
             table weight × point, zero weights skipped. Writes ROWS_PER_N·n + ROWS_FIXED points \
             from `out_base`. A crease or corner vertex (a non-empty `vertex_sectors` range) \
             sums each sector's rows over its partial ring [p, q_0, d_0, .., q_m] instead: \
             per-position outputs at the sector's ring positions, single outputs from the \
             sector at position 0, so every value is computed once (docs/boundaries.md §4).",
            s.name
        ),
    );
    let vertex = f.param("vertex", Ty::U32);
    let out_base = f.param("out_base", Ty::U32);
    let n = f.local("n", Ty::U32);
    let ring_base = f.local("ring_base", Ty::U32);
    let base = f.local("row_base", Ty::U32);
    let rows = f.local("rows", Ty::U32);
    let slots = f.local("slots", Ty::U32);
    let r = f.local("r", Ty::U32);
    let acc = f.local("acc", Ty::Vec3);
    let k = f.local("k", Ty::U32);
    let w = f.local("w", Ty::F32);
    let first = f.local("first_sector", Ty::U32);
    let end = f.local("end_sector", Ty::U32);
    let sec = f.local("s", Ty::U32);
    let rec = f.local("record", Ty::U32);
    let m = f.local("m", Ty::U32);
    let count = f.local("count", Ty::U32);
    let j0 = f.local("j0", Ty::U32);
    let sring = f.local("sector_ring", Ty::U32);
    let sbase = f.local("sector_row", Ty::U32);
    let sslots = f.local("sector_slots", Ty::U32);
    let j = f.local("j", Ty::U32);

    // Smooth vertices: every row of the valence block, in row order.
    let mut smooth = vec![
        Stmt::Let(ring_base, fetch(Resource::RingOffsets, l(vertex))),
        Stmt::Let(base, Expr::ConstIndex(row_base, Box::new(l(n)))),
        Stmt::Let(rows, add(mul(u(ra), l(n)), u(rb))),
        Stmt::Let(slots, add(mul(u(2), l(n)), u(1))),
    ];
    let mut per_row = sum_row(acc, k, w, add(l(base), l(r)), None, ring_base, slots);
    per_row.push(Stmt::Store(
        Resource::VertexOut,
        add(l(out_base), l(r)),
        l(acc),
    ));
    smooth.push(Stmt::For(r, u(0), l(rows), per_row));

    // Sectored vertices: per sector, per output.
    let words = crate::plan::abi::SECTOR_WORDS;
    let field = |i: u32| fetch(Resource::Sectors, add(l(rec), u(i)));
    let mut body = vec![
        Stmt::Let(rec, mul(l(sec), u(words))),
        Stmt::Let(m, field(1)),
        Stmt::Let(count, field(2)),
        Stmt::Let(j0, field(3)),
        Stmt::Let(sring, field(4)),
        Stmt::Let(
            sbase,
            Expr::ConstIndex(
                sector.row_base,
                Box::new(sub(
                    add(mul(field(0), Expr::Const(sector.max_faces)), l(m)),
                    u(1),
                )),
            ),
        ),
        Stmt::Let(sslots, add(mul(u(2), l(m)), u(2))),
    ];
    for (def, d) in s.outputs() {
        let (a, b) = s.output_offset(def);
        // Row of (def, j) in the sector block: a·(m + 1) + b + j; its
        // destination: out_base + a·n + b (+ j0 + j).
        let block_row = add(l(sbase), add(mul(u(a), add(l(m), u(1))), u(b)));
        let dest = add(l(out_base), add(mul(u(a), l(n)), u(b)));
        let col = Some(Expr::Const(sector.column));
        if d.indexed {
            let mut inner = sum_row(acc, k, w, add(block_row, l(j)), col, sring, sslots);
            inner.push(Stmt::Store(
                Resource::VertexOut,
                add(dest, add(l(j0), l(j))),
                l(acc),
            ));
            body.push(Stmt::For(j, u(0), l(count), inner));
        } else {
            let mut inner = sum_row(acc, k, w, block_row, col, sring, sslots);
            inner.push(Stmt::Store(Resource::VertexOut, dest, l(acc)));
            body.push(Stmt::If(bin(BinOp::Eq, l(j0), u(0)), inner, vec![]));
        }
    }
    let sectored = vec![Stmt::For(sec, l(first), l(end), body)];

    f.body = vec![
        Stmt::Let(n, fetch(Resource::Valence, l(vertex))),
        Stmt::Let(first, fetch(Resource::VertexSectors, l(vertex))),
        Stmt::Let(end, fetch(Resource::VertexSectors, add(l(vertex), u(1)))),
        Stmt::If(bin(BinOp::Eq, l(first), l(end)), smooth, sectored),
    ];
    f
}

//! The GPU-driven adaptive buckets (WGSL): the count, plan and scatter
//! passes of the stable compaction of `patch_levels` into `bucket_list`,
//! the indirect arguments, and the evaluation entries that read them.

use super::*;

/// Head of a chunk pass (`adaptive_count_main`, `adaptive_scatter_main`): a
/// workgroup of [`BUCKET_CHUNK`] invocations per chunk of the class range
/// `first .. first + count`; invocation l loads patch `p = BUCKET_CHUNK·c +
/// l`'s bucket level into the shared tile (0 outside the range), then the
/// workgroup synchronises. Returns `c`, `p`, `lv`.
fn chunk_head(f: &mut Function) -> (LocalId, LocalId, LocalId) {
    let c = f.local("c", Ty::U32);
    let p = f.local("p", Ty::U32);
    let lv = f.local("lv", Ty::U32);
    let li = stage(StageIn::LocalIndex);
    f.body = vec![
        Stmt::Let(
            c,
            add(
                div(param("first"), u(BUCKET_CHUNK)),
                stage(StageIn::WorkgroupId),
            ),
        ),
        Stmt::Let(p, add(mul(u(BUCKET_CHUNK), l(c)), li.clone())),
        Stmt::Var(lv, u(0)),
        Stmt::If(
            bin(
                BinOp::And,
                bin(BinOp::Ge, l(p), param("first")),
                lt(l(p), add(param("first"), param("count"))),
            ),
            vec![Stmt::Assign(
                lv,
                fetch_at(
                    Resource::PatchLevels,
                    mul(u(PATCH_LEVELS_WORDS), l(p)),
                    PATCH_LEVELS_WORDS - 1,
                ),
            )],
            vec![],
        ),
        Stmt::Store(Resource::BucketTile, li, l(lv)),
        Stmt::Barrier(Barrier::Workgroup),
    ];
    (c, p, lv)
}

const CHUNK_PASS: EntryKind = EntryKind::Compute {
    workgroup_size: BUCKET_CHUNK,
};

/// GPU-driven buckets: the lists of `bucket_patches` and the indirect
/// dispatch arguments built on the GPU from `patch_levels`, so nothing is
/// read back before the evaluation. Per class range r (slots `16r + j`,
/// bucket `2^j`), a stable parallel compaction over chunks of
/// [`BUCKET_CHUNK`] patches (chunk c = patches `256c ..`, a workgroup
/// each): `adaptive_count_main` counts each chunk's patches per bucket into
/// `bucket_chunks`, `adaptive_plan_main` (one workgroup) turns the chunk
/// counts into each chunk's offset within its slot (one invocation per
/// slot, a scan over the chunks), then prefix-sums the slots into first
/// entry and first sample and writes the indirect arguments, and
/// `adaptive_scatter_main` writes every patch at the sum of its slot's
/// first entry, its chunk's offset and its rank among the chunk's earlier
/// patches of the same bucket. The entries come out in patch order — the
/// order the host lists have — without atomics, and no invocation loops
/// over more than one chunk's patches (the plan's scan: over the chunks).
/// `eval_adaptive_indirect_main` runs one indirect dispatch per slot.
/// `bucket_list` (written here) is bound as `bucket_patches` for the
/// evaluation: a header of 4 u32 per slot (count, first entry, first
/// sample, x workgroups), then the entries.
pub(super) fn gpu_driven(entries: &Entries) -> Vec<EntryItem> {
    let [grid_len, grid_iu, grid_iv] = entries.grid.map(FnRef::Local);
    let (slots, chunk) = (BUCKET_SLOTS, BUCKET_CHUNK);
    let li = || stage(StageIn::LocalIndex);
    let tile = |i: Expr| fetch(Resource::BucketTile, i);
    let mut items = vec![EntryItem::Workgroup {
        resource: Resource::BucketTile,
        len: chunk,
        doc: "One chunk's bucket levels (0 = no patch of the dispatch's class range), shared by the\n\
              workgroup of adaptive_count_main / adaptive_scatter_main."
            .into(),
    }];

    let mut f = compute(
        "adaptive_count_main",
        &format!(
            "GPU-driven buckets 1: for the class range of patches first .. first + count, workgroup w is\n\
             chunk c = first / {chunk} + w (patches {chunk}c ..); invocation l < {slots} counts the chunk's patches of\n\
             the range whose bucket (patch_levels[5p + 4]) is 2^l into bucket_chunks[2c·level + out_base + l]\n\
             (level = the number of slots; row c: the counts, then the offsets)."
        ),
    );
    let (c, _, _) = chunk_head(&mut f);
    let n = f.local("n", Ty::U32);
    let m = f.local("m", Ty::U32);
    f.body.push(Stmt::If(
        lt(li(), u(slots)),
        vec![
            Stmt::Var(n, u(0)),
            Stmt::ForStep(
                m,
                u(0),
                u(chunk),
                u(1),
                vec![Stmt::If(
                    eq(tile(l(m)), shl(u(1), li())),
                    vec![Stmt::Assign(n, add(l(n), u(1)))],
                    vec![],
                )],
            ),
            Stmt::Store(
                Resource::BucketChunks,
                add(
                    mul(mul(u(2), l(c)), param("level")),
                    add(param("out_base"), li()),
                ),
                l(n),
            ),
        ],
        vec![],
    ));
    items.push(entry(
        CHUNK_PASS,
        vec![StageIn::WorkgroupId, StageIn::LocalIndex],
        f,
    ));

    items.push(entry(
        COMPUTE,
        vec![StageIn::LocalIndex],
        plan_pass(entries, grid_len),
    ));

    let mut f = compute(
        "adaptive_scatter_main",
        "GPU-driven buckets 3: for the class range of patches first .. first + count, chunk c as in 1;\n\
         the chunk's patch p of bucket 2^j goes to entry (first entry of slot out_base + j) + (the chunk's\n\
         offset in bucket_chunks) + (its rank among the chunk's earlier patches of bucket 2^j), at\n\
         bucket_list[4·level + 6·entry ..] (level = the number of slots, the header's length / 4):\n\
         patch, first control point, edge levels.",
    );
    let (c, p, lv) = chunk_head(&mut f);
    let j = f.local("j", Ty::U32);
    f.body.push(Stmt::Let(
        j,
        Expr::Call(Builtin::CountTrailingZeros, vec![l(lv)]),
    ));
    let (points, mut inner) = points_of_class(&mut f, entries);
    let rank = f.local("rank", Ty::U32);
    let m = f.local("m", Ty::U32);
    let slot = f.local("slot", Ty::U32);
    let at = f.local("at", Ty::U32);
    let header = |k: u32| {
        fetch_at(
            Resource::BucketList,
            mul(u(BUCKET_HEADER_WORDS), l(slot)),
            k,
        )
    };
    inner.extend([
        Stmt::Var(rank, u(0)),
        Stmt::ForStep(
            m,
            u(0),
            li(),
            u(1),
            vec![Stmt::If(
                eq(tile(l(m)), l(lv)),
                vec![Stmt::Assign(rank, add(l(rank), u(1)))],
                vec![],
            )],
        ),
        Stmt::Let(slot, add(param("out_base"), l(j))),
        Stmt::Let(
            at,
            add(
                mul(u(BUCKET_HEADER_WORDS), param("level")),
                mul(
                    u(BUCKET_ENTRY_WORDS),
                    add(
                        add(
                            header(1),
                            fetch(
                                Resource::BucketChunks,
                                add(mul(add(mul(u(2), l(c)), u(1)), param("level")), l(slot)),
                            ),
                        ),
                        l(rank),
                    ),
                ),
            ),
        ),
        Stmt::Store(Resource::BucketList, l(at), l(p)),
        Stmt::Store(
            Resource::BucketList,
            add(l(at), u(1)),
            add(param("cp_base"), mul(sub(l(p), param("first")), l(points))),
        ),
    ]);
    for e in 0..4 {
        inner.push(Stmt::Store(
            Resource::BucketList,
            add(l(at), u(e + 2)),
            fetch_at(Resource::PatchLevels, mul(u(PATCH_LEVELS_WORDS), l(p)), e),
        ));
    }
    f.body.push(Stmt::If(
        bin(BinOp::And, lt(l(j), u(slots)), eq(l(lv), shl(u(1), l(j)))),
        inner,
        vec![],
    ));
    items.push(entry(
        CHUNK_PASS,
        vec![StageIn::WorkgroupId, StageIn::LocalIndex],
        f,
    ));

    let mut f = compute(
        "eval_adaptive_indirect_main",
        "GPU-driven buckets 4, one indirect dispatch per slot out_base (class, level = its bucket):\n\
         the slot's header in bucket_patches (count, first entry, first sample, x workgroups),\n\
         entries after the header (first = the number of slots), samples from the slot's first sample.",
    );
    let h = f.local("h", Ty::U32);
    let (k, spp, patch, s, iu, iv) = grid_locals(&mut f);
    let head = |k: u32| {
        if k == 0 {
            fetch(Resource::BucketPatches, l(h))
        } else {
            fetch_at(Resource::BucketPatches, l(h), k)
        }
    };
    f.body = vec![
        Stmt::Let(h, mul(u(BUCKET_HEADER_WORDS), param("out_base"))),
        Stmt::Let(
            k,
            add(
                stage(StageIn::GlobalId),
                mul(mul(stage(StageIn::GlobalIdY), head(3)), u(WORKGROUP_SIZE)),
            ),
        ),
        Stmt::Let(spp, call(grid_len, vec![param("level")])),
        return_if(bin(BinOp::Ge, l(k), mul(head(0), l(spp)))),
    ];
    f.body
        .extend(split_sample(k, spp, patch, s, iu, iv, grid_iu, grid_iv));
    let e = f.local("e", Ty::U32);
    f.body.push(Stmt::Let(
        e,
        add(
            mul(u(BUCKET_HEADER_WORDS), param("first")),
            mul(u(BUCKET_ENTRY_WORDS), add(head(1), l(patch))),
        ),
    ));
    let (result, body) = adaptive_sample(&mut f, entries, e, iu, iv);
    f.body.extend(body);
    let out = sample_out(&mut f, add(head(2), l(k)), result);
    f.body.extend(out);
    items.push(entry(COMPUTE, vec![StageIn::GlobalId], f));

    let mut f = Function::new(
        "eval_adaptive_indirect_vs",
        "GPU-driven buckets 4, drawn: one draw_indexed_indirect per slot out_base (bucket_draw's\n\
         arguments) of the slot's level grid, instance inst = entry inst of the slot (header in\n\
         bucket_patches, entries after it: first = the number of slots).",
    );
    let h = f.local("h", Ty::U32);
    f.body
        .push(Stmt::Let(h, mul(u(BUCKET_HEADER_WORDS), param("out_base"))));
    let (iu, iv, e) = vs_head(&mut f, grid_iu, grid_iv);
    f.body.push(Stmt::Let(
        e,
        add(
            mul(u(BUCKET_HEADER_WORDS), param("first")),
            mul(
                u(BUCKET_ENTRY_WORDS),
                add(
                    fetch_at(Resource::BucketPatches, l(h), 1),
                    stage(StageIn::InstanceIndex),
                ),
            ),
        ),
    ));
    items.push(adaptive_vs(f, entries, iu, iv, e));
    items
}

/// `adaptive_plan_main` (one workgroup): the chunk scan per slot, then the
/// slots' first entries, first samples and indirect arguments.
fn plan_pass(entries: &Entries, grid_len: FnRef) -> Function {
    let slots = BUCKET_SLOTS;
    let wg = WORKGROUP_SIZE;
    let mut f = compute(
        "adaptive_plan_main",
        &format!(
            "GPU-driven buckets 2 (one workgroup): invocation s (and s + 64, …) < count scans slot s's\n\
             chunk counts (bucket_chunks[2c·count + s], chunk rows c < first) into each chunk's offset within\n\
             the slot (exclusive prefix, at 2c·count + count + s) and the total into the slot's header; then\n\
             invocation 0, for slots 0 .. count, writes the first entry and first sample (prefix sums of\n\
             count and count·grid_len(2^(slot % 16))), the indirect dispatch arguments\n\
             (y = ⌈workgroups / {INDIRECT_X}⌉ rows of x = ⌈workgroups / y⌉) and the indexed indirect draw arguments\n\
             (the level's grid, one instance per patch) into bucket_list, bucket_dispatch and bucket_draw."
        ),
    );
    let s = f.local("s", Ty::U32);
    // One `n` per loop: each loop body declares it afresh.
    let n = f.local("n", Ty::U32);
    let c = f.local("c", Ty::U32);
    let at = f.local("at", Ty::U32);
    let entry = f.local("entry", Ty::U32);
    let first_sample = f.local("first_sample", Ty::U32);
    let b = f.local("b", Ty::U32);
    let spp = f.local("spp", Ty::U32);
    let groups = f.local("groups", Ty::U32);
    let y = f.local("y", Ty::U32);
    let x = f.local("x", Ty::U32);
    let lb = f.local("lb", Ty::U32);
    let li = stage(StageIn::LocalIndex);
    let bucket = || rem(l(b), u(slots));
    // The level's grid: 2·L² (quads) or L² (triangles) triangles.
    let per_cell = if entries.sides == 4 { 6 } else { 3 };
    let at_b = |stride: u32, k: u32| {
        let base = mul(u(stride), l(b));
        if k == 0 {
            base
        } else {
            add(base, u(k))
        }
    };
    let mut per_slot = vec![
        Stmt::Let(n, fetch(Resource::BucketList, at_b(BUCKET_HEADER_WORDS, 0))),
        Stmt::Let(spp, call(grid_len, vec![shl(u(1), bucket())])),
        Stmt::Let(groups, div(add(mul(l(n), l(spp)), u(wg - 1)), u(wg))),
        // As few rows y as the x limit allows, then the narrowest x for
        // them: fewer than y idle workgroups (x = min(groups, limit) would
        // leave up to limit − 1 of them in the last row).
        Stmt::Let(y, div(add(l(groups), u(INDIRECT_X - 1)), u(INDIRECT_X))),
        Stmt::Var(x, u(0)),
        Stmt::If(
            bin(BinOp::Gt, l(y), u(0)),
            vec![Stmt::Assign(x, div(add(l(groups), sub(l(y), u(1))), l(y)))],
            vec![],
        ),
        Stmt::Store(Resource::BucketList, at_b(BUCKET_HEADER_WORDS, 1), l(entry)),
        Stmt::Store(
            Resource::BucketList,
            at_b(BUCKET_HEADER_WORDS, 2),
            l(first_sample),
        ),
        Stmt::Store(Resource::BucketList, at_b(BUCKET_HEADER_WORDS, 3), l(x)),
        Stmt::Store(
            Resource::BucketDispatch,
            at_b(BUCKET_DISPATCH_WORDS, 0),
            l(x),
        ),
        Stmt::Store(
            Resource::BucketDispatch,
            at_b(BUCKET_DISPATCH_WORDS, 1),
            l(y),
        ),
        Stmt::Store(
            Resource::BucketDispatch,
            at_b(BUCKET_DISPATCH_WORDS, 2),
            u(1),
        ),
        Stmt::Let(lb, shl(u(1), bucket())),
        Stmt::Store(
            Resource::BucketDraw,
            at_b(BUCKET_DRAW_WORDS, 0),
            mul(u(per_cell), mul(l(lb), l(lb))),
        ),
        Stmt::Store(Resource::BucketDraw, at_b(BUCKET_DRAW_WORDS, 1), l(n)),
    ];
    for k in 2..BUCKET_DRAW_WORDS {
        per_slot.push(Stmt::Store(
            Resource::BucketDraw,
            at_b(BUCKET_DRAW_WORDS, k),
            u(0),
        ));
    }
    per_slot.extend([
        Stmt::Assign(entry, add(l(entry), l(n))),
        Stmt::Assign(first_sample, add(l(first_sample), mul(l(n), l(spp)))),
    ]);
    let chunk_row = |s: Expr| add(mul(mul(u(2), l(c)), param("count")), s);
    f.body = vec![
        Stmt::ForStep(
            s,
            li.clone(),
            param("count"),
            u(wg),
            vec![
                Stmt::Var(n, u(0)),
                Stmt::ForStep(
                    c,
                    u(0),
                    param("first"),
                    u(1),
                    vec![
                        Stmt::Let(at, chunk_row(l(s))),
                        Stmt::Store(Resource::BucketChunks, add(l(at), param("count")), l(n)),
                        Stmt::Assign(n, add(l(n), fetch(Resource::BucketChunks, l(at)))),
                    ],
                ),
                Stmt::Store(
                    Resource::BucketList,
                    mul(u(BUCKET_HEADER_WORDS), l(s)),
                    l(n),
                ),
            ],
        ),
        Stmt::Barrier(Barrier::Storage),
        return_if(bin(BinOp::Ne, li, u(0))),
        Stmt::Var(entry, u(0)),
        Stmt::Var(first_sample, u(0)),
        Stmt::ForStep(b, u(0), param("count"), u(1), per_slot),
    ];
    f
}

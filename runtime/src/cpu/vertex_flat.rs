//! The flat vertex stage: the generated smooth-vertex path (DESIGN.md
//! Rule 1: every output row the sum over ring slots `0..2n` in ring order of
//! table weight × point, zero weights skipped) with its per-valence work
//! done once per topology instead of once per vertex per deformation, and
//! eight vertices of one valence summed at once.
//!
//! The generated `vertex_stage` reads, for every vertex and row, all
//! `2n + 1` table weights of that row, tests each against zero and fetches
//! the point through the ring for each non-zero one. Here the non-zero
//! weights of each valence's rows are listed once ([`FlatVertexStage::new`],
//! in slot order, from the same table cells). Vertices of the same valence
//! run the very same term list, so they are grouped into chunks of
//! [`LANES`] (per block of vertices, so every parallel task still writes
//! one contiguous slice of `vertex_out`): the chunk's ring points are
//! gathered once into structure-of-arrays lanes (`p[slot][component][lane]`,
//! from a gather list made at `new`), and each term is then one lane-wise
//! multiply and one lane-wise add per component — exactly the generated
//! `acc = acc + p_k · w_k` of every lane's vertex, in the same order, with
//! one IEEE rounding each (Rust never contracts to FMA, and LLVM vectorises
//! these loops across lanes only, never within one sum). The outputs are
//! therefore bit-identical to the generated kernel's
//! (tests/tests/grid_path.rs). Crease and corner vertices (a non-empty
//! sector range) keep the generated kernel.
//!
//! The lane loops are plain arrays for LLVM to vectorise; an AVX2 copy is
//! chosen at run time ([`Isa`]), and both copies give the same bits.

use super::grid_eval::Isa;
use crate::kernels::common::{SchemeKernels, TABLE_WIDTH};
use crate::mesh::topology::Topology;
use glam::Vec3;

/// Largest ring of a smooth vertex: `2·MAX_VALENCE + 1` slots.
const MAX_SLOTS: usize = 2 * crate::kernels::common::MAX_VALENCE as usize + 1;

/// Vertices summed at once: one AVX2 register of f32 per component.
pub(crate) const LANES: usize = 8;

/// One non-zero term of a row: ring slot and table weight.
#[derive(Clone, Copy, Debug)]
struct Term {
    slot: u32,
    weight: f32,
}

/// Up to [`LANES`] smooth vertices of one valence in one block.
#[derive(Clone, Copy, Debug)]
struct Chunk {
    /// Valence of every lane's vertex.
    n: u32,
    /// Lanes in use (the rest repeat lane 0's ring and are not written).
    lanes: u32,
    /// Rows computed and written per lane: the valence's first `rows`
    /// (all of them unless no face reads the rest, see
    /// [`FlatVertexStage::new`]).
    rows: u32,
    /// First entry in `gather` (`slots × LANES` position indices,
    /// slot-major).
    gather: u32,
    /// Each lane's first output, relative to its block's first output.
    out: [u32; LANES],
    /// Whether every ring index is below the last vertex, so that the AVX2
    /// copy may load 16 bytes (the point and the next one's `x`) per point.
    wide: bool,
}

/// The work of one block of vertices: its chunks and the vertices the
/// generated kernel computes.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct BlockPlan {
    chunks: (u32, u32),
    kernel: (u32, u32),
}

/// Sparse per-valence rows of one scheme's smooth vertex stage, and the
/// per-block chunks that run them.
#[derive(Clone, Debug)]
pub(crate) struct FlatVertexStage {
    /// Per valence `n`: range of its rows in `rows` (empty if no smooth
    /// vertex of this valence exists).
    valence_rows: Vec<(u32, u32)>,
    /// Per row: range of its terms in `terms`.
    rows: Vec<(u32, u32)>,
    terms: Vec<Term>,
    chunks: Vec<Chunk>,
    /// Position index per (chunk, slot, lane).
    gather: Vec<u32>,
    /// Vertices left to the generated kernel, block by block.
    kernel_vertices: Vec<u32>,
    /// Per block of `block` vertices.
    blocks: Vec<BlockPlan>,
    isa: Isa,
    /// Vertices of the topology: `positions` must be at least this long.
    vertices: usize,
}

impl FlatVertexStage {
    /// The rows of every valence a smooth vertex of `topo` has, read from
    /// `table` where the generated kernel reads them, and the chunks of
    /// every block of `block` vertices (`offsets`: the `vertex_out` layout).
    ///
    /// `read[v]` is how many of vertex `v`'s first rows some face reads
    /// (at most all of them): the flat path computes only those. A
    /// vertex whose faces only copy `v`, `e` and `f` (PCCM's ordinary
    /// quads) skips rows such as PCCM's `t` or Gregory's `r`, which only
    /// the extraordinary faces read; those entries of `vertex_out` are not
    /// written. Vertices the generated kernel runs compute every row.
    pub(crate) fn new(
        topo: &Topology,
        scheme: &SchemeKernels,
        table: &[f32],
        offsets: &[u32],
        block: usize,
        read: &[u32],
    ) -> Self {
        let mut flat = FlatVertexStage {
            valence_rows: Vec::new(),
            rows: Vec::new(),
            terms: Vec::new(),
            chunks: Vec::new(),
            gather: Vec::new(),
            kernel_vertices: Vec::new(),
            blocks: Vec::new(),
            isa: if topo.valence.len() < i32::MAX as usize / 3 {
                Isa::detect()
            } else {
                Isa::Baseline
            },
            vertices: topo.valence.len(),
        };
        flat.list_rows(topo, scheme, table);
        let vertices = topo.valence.len();
        // Per valence: groups of vertices computing the same rows.
        let mut by_valence: Vec<Vec<(u32, Vec<u32>)>> = vec![Vec::new(); flat.valence_rows.len()];
        for first in (0..vertices).step_by(block.max(1)) {
            let last = (first + block).min(vertices);
            let base = offsets[first];
            let (c0, k0) = (flat.chunks.len() as u32, flat.kernel_vertices.len() as u32);
            for v in first..last {
                if offsets[v + 1] == offsets[v] {
                    continue;
                }
                if flat.covers(topo, v) {
                    let (a, b) = flat.valence_rows[topo.valence[v] as usize];
                    let rows = read.get(v).map_or(b - a, |&r| r.min(b - a));
                    if rows == 0 {
                        continue;
                    }
                    let groups = &mut by_valence[topo.valence[v] as usize];
                    match groups.iter_mut().find(|(r, _)| *r == rows) {
                        Some((_, g)) => g.push(v as u32),
                        None => groups.push((rows, vec![v as u32])),
                    }
                } else {
                    flat.kernel_vertices.push(v as u32);
                }
            }
            for (n, groups) in by_valence.iter_mut().enumerate() {
                for (rows, group) in groups.iter_mut() {
                    for lanes in group.chunks(LANES) {
                        flat.push_chunk(topo, (n as u32, *rows), lanes, offsets, base);
                    }
                    group.clear();
                }
            }
            flat.blocks.push(BlockPlan {
                chunks: (c0, flat.chunks.len() as u32),
                kernel: (k0, flat.kernel_vertices.len() as u32),
            });
        }
        flat
    }

    /// The non-zero terms of every row of every valence a smooth vertex
    /// has, in slot order.
    fn list_rows(&mut self, topo: &Topology, scheme: &SchemeKernels, table: &[f32]) {
        let max_n = topo.valence.iter().copied().max().unwrap_or(0) as usize;
        self.valence_rows = vec![(0, 0); max_n + 1];
        let mut needed = vec![false; max_n + 1];
        for (v, &n) in topo.valence.iter().enumerate() {
            if n > 0 && smooth(topo, v) {
                needed[n as usize] = true;
            }
        }
        for (n, _) in needed.iter().enumerate().filter(|(_, &x)| x) {
            let Some(&row_base) = scheme.row_base.get(n) else {
                continue;
            };
            let n32 = n as u32;
            let rows = scheme.rows_per_n * n32 + scheme.rows_fixed;
            let first = self.rows.len() as u32;
            for r in 0..rows {
                let start = self.terms.len() as u32;
                for k in 0..2 * n32 + 1 {
                    let cell = ((row_base + r) * TABLE_WIDTH + k) as usize;
                    let w = table.get(cell).copied().unwrap_or(0.0);
                    if w != 0.0f32 {
                        self.terms.push(Term { slot: k, weight: w });
                    }
                }
                self.rows.push((start, self.terms.len() as u32));
            }
            self.valence_rows[n] = (first, self.rows.len() as u32);
        }
    }

    /// One chunk of `lanes` (1..=LANES vertices of valence `n`, computing
    /// their first `rows` rows), its ring gathered slot-major; unused lanes
    /// repeat lane 0.
    fn push_chunk(
        &mut self,
        topo: &Topology,
        (n, rows): (u32, u32),
        lanes: &[u32],
        offsets: &[u32],
        base: u32,
    ) {
        let slots = 2 * n as usize + 1;
        let lane = |l: usize| if l < lanes.len() { lanes[l] } else { lanes[0] };
        let gather = self.gather.len() as u32;
        let last_vertex = topo.valence.len().saturating_sub(1) as u32;
        let mut wide = true;
        for k in 0..slots {
            for l in 0..LANES {
                let v = lane(l) as usize;
                let i = topo.ring[topo.ring_offsets[v] as usize + k];
                wide &= i < last_vertex;
                self.gather.push(i);
            }
        }
        let mut out = [0u32; LANES];
        for (l, o) in out.iter_mut().enumerate() {
            *o = offsets[lane(l) as usize] - base;
        }
        self.chunks.push(Chunk {
            n,
            lanes: lanes.len() as u32,
            rows,
            gather,
            out,
            wide,
        });
    }

    /// The rows chunk `c` computes: its valence's first `c.rows`.
    fn chunk_rows(&self, c: &Chunk) -> &[(u32, u32)] {
        let (first, last) = self.valence_rows[c.n as usize];
        let rows = &self.rows[first as usize..last as usize];
        &rows[..(c.rows as usize).min(rows.len())]
    }

    /// Whether vertex `v` takes the flat path (smooth, with its valence's
    /// rows listed).
    pub(crate) fn covers(&self, topo: &Topology, v: usize) -> bool {
        let n = topo.valence[v] as usize;
        let ring = topo.ring_offsets[v] as usize;
        smooth(topo, v)
            && 2 * n < MAX_SLOTS
            && self
                .valence_rows
                .get(n)
                .is_some_and(|&(a, b)| b > a && (b - a) as usize <= MAX_ROWS)
            && topo
                .ring
                .get(ring..ring + 2 * n + 1)
                .is_some_and(|r| r.iter().all(|&i| (i as usize) < topo.valence.len()))
    }

    /// The vertices of block `b` that the generated kernel computes.
    pub(crate) fn kernel_vertices(&self, b: usize) -> &[u32] {
        let (k0, k1) = self.blocks[b].kernel;
        &self.kernel_vertices[k0 as usize..k1 as usize]
    }

    /// The flat vertices of block `b` into `out` (the block's slice of
    /// `vertex_out`), from `positions`.
    pub(crate) fn block(
        &self,
        b: usize,
        positions: &[Vec3],
        out: &mut [Vec3],
        scratch: &mut Scratch,
    ) {
        let (c0, c1) = self.blocks[b].chunks;
        let chunks = &self.chunks[c0 as usize..c1 as usize];
        match self.isa {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Isa::Avx2` and `Isa::Avx512` are only produced
            // after `is_x86_feature_detected!("avx2")`, and the positions
            // are long enough for every gather index.
            isa if isa.has_avx2() && positions.len() >= self.vertices => unsafe {
                self.chunks_avx2(chunks, positions, out, scratch)
            },
            _ => self.chunks_baseline(chunks, positions, out, &mut scratch.p),
        }
    }

    /// This stage with the baseline copy of the lane loops even where AVX2
    /// is available (the tests check both copies give the same bits).
    pub(crate) fn force_baseline(&mut self) {
        self.isa = Isa::Baseline;
    }

    fn chunks_baseline(
        &self,
        chunks: &[Chunk],
        positions: &[Vec3],
        out: &mut [Vec3],
        p: &mut Lanes,
    ) {
        for c in chunks {
            self.chunk(c, positions, p, out, row_baseline);
        }
    }

    /// The chunks with AVX2: the ring loaded a point at a time and
    /// transposed ([`load_transposed`]; `vgatherdps` for a chunk whose ring
    /// holds the last vertex, where a 16-byte load would end past
    /// `positions`), each row's sums in three registers ([`row_avx2`]), all
    /// rows of the chunk kept, then written per lane as contiguous floats
    /// through 8×8 transposes (the lane's outputs are `rows` consecutive
    /// `Vec3`s).
    /// Only data movement differs from [`Self::chunk`]; every sum is the
    /// same sequence of `×` and `+`.
    ///
    /// # Safety
    /// AVX2 must be available; `positions.len()` must be at least the
    /// topology's vertex count (every gather index is a ring entry, below
    /// it, and below `i32::MAX / 3`: checked in [`Self::new`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn chunks_avx2(
        &self,
        chunks: &[Chunk],
        positions: &[Vec3],
        out: &mut [Vec3],
        scratch: &mut Scratch,
    ) {
        use std::arch::x86_64::*;
        let Scratch { p, acc } = scratch;
        let base = positions.as_ptr() as *const f32;
        let out_len = out.len();
        let out_f = out.as_mut_ptr() as *mut f32;
        for c in chunks {
            let n = c.n as usize;
            let slots = 2 * n + 1;
            let gather = &self.gather[c.gather as usize..][..slots * LANES];
            for (pk, idx) in p[..slots].iter_mut().zip(gather.chunks_exact(LANES)) {
                if c.wide {
                    // SAFETY: every index `i` is below the last vertex, so
                    // the 16 bytes from point `i` lie inside `positions`.
                    unsafe { load_transposed(base, idx, pk) };
                    continue;
                }
                // SAFETY: `idx` is 8 u32; every index `i` has
                // `3i + 2 < 3·positions.len()` and fits i32 (see above).
                unsafe {
                    let vi = _mm256_loadu_si256(idx.as_ptr() as *const __m256i);
                    let v3 = _mm256_add_epi32(_mm256_add_epi32(vi, vi), vi);
                    let x = _mm256_i32gather_ps::<4>(base, v3);
                    let y = _mm256_i32gather_ps::<4>(base.add(1), v3);
                    let z = _mm256_i32gather_ps::<4>(base.add(2), v3);
                    _mm256_storeu_ps(pk[0].as_mut_ptr(), x);
                    _mm256_storeu_ps(pk[1].as_mut_ptr(), y);
                    _mm256_storeu_ps(pk[2].as_mut_ptr(), z);
                }
            }
            let rows = self.chunk_rows(c);
            for (s, &(a, b)) in acc.iter_mut().zip(rows) {
                // SAFETY: AVX2 is available (this function's contract).
                unsafe { row_avx2(&self.terms[a as usize..b as usize], p, s) };
            }
            let lanes = &c.out[..c.lanes as usize];
            let floats = 3 * rows.len();
            // Each used lane's outputs lie inside `out` (so the stores
            // below stay in bounds).
            if lanes
                .iter()
                .any(|&o| o as usize + rows.len() > out_len || rows.len() > MAX_ROWS)
            {
                self.chunk(c, positions, p, out, row_baseline);
                continue;
            }
            let flat = acc.as_flattened();
            for k in (0..floats).step_by(LANES) {
                // A last partial register is stored whole, ending at the
                // lane's last float: it starts `LANES − left` floats early
                // and writes again, with the same bits, floats the
                // previous store wrote. (`vmaskmovps` stores cost about 8%
                // of this stage on Zen 3.) Only a lane of fewer than 8
                // floats needs the mask.
                let left = floats - k;
                let at = if left < LANES && floats >= LANES {
                    floats - LANES
                } else {
                    k
                };
                // SAFETY: `flat` holds `3·MAX_ROWS` (a multiple of 8) rows
                // of 8 lanes and `at + 8 <= 3·MAX_ROWS`; each lane's stores
                // cover floats `3o + at .. 3o + min(at + 8, floats)` of a
                // lane whose outputs are inside `out` (checked above;
                // `Vec3` is three packed f32).
                unsafe {
                    let t = transpose8(&flat[at..at + LANES]);
                    let mask = _mm256_cmpgt_epi32(
                        _mm256_set1_epi32((floats - at) as i32),
                        _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7),
                    );
                    for (l, &o) in lanes.iter().enumerate() {
                        let dst = out_f.add(3 * o as usize + at);
                        if floats - at >= LANES {
                            _mm256_storeu_ps(dst, t[l]);
                        } else {
                            _mm256_maskstore_ps(dst, mask, t[l]);
                        }
                    }
                }
            }
        }
    }

    /// One chunk: its ring gathered into the lanes of `p` (scratch shared
    /// by a block's chunks, so it is not cleared per chunk: every slot
    /// read is written first), then every row's sum lane-wise (`row`),
    /// written to each used lane's output.
    #[inline(always)]
    fn chunk(
        &self,
        c: &Chunk,
        positions: &[Vec3],
        p: &mut Lanes,
        out: &mut [Vec3],
        row: impl Fn(&[Term], &Lanes, &mut [[f32; LANES]; 3]),
    ) {
        let n = c.n as usize;
        let slots = 2 * n + 1;
        let gather = &self.gather[c.gather as usize..][..slots * LANES];
        for (pk, idx) in p[..slots].iter_mut().zip(gather.chunks_exact(LANES)) {
            for (l, &i) in idx.iter().enumerate() {
                let q = positions[i as usize];
                pk[0][l] = q.x;
                pk[1][l] = q.y;
                pk[2][l] = q.z;
            }
        }
        let rows = self.chunk_rows(c);
        let lanes = &c.out[..c.lanes as usize];
        let mut s = [[0.0f32; LANES]; 3];
        for (r, &(a, b)) in rows.iter().enumerate() {
            row(&self.terms[a as usize..b as usize], p, &mut s);
            for (l, &o) in lanes.iter().enumerate() {
                out[o as usize + r] = Vec3::new(s[0][l], s[1][l], s[2][l]);
            }
        }
    }
}

/// The points `idx` (8 lanes) of `base` into `pk` as x, y and z rows: one
/// 16-byte load per point (its x, y, z and the next point's x, unused),
/// two points per register, and a 4×4 transpose within each 128-bit half.
/// On Zen 3 three `vgatherdps` per slot took about 40 % of the stage's
/// time; these loads and shuffles move the same bits.
///
/// # Safety
/// AVX2 must be available; for every `i` in `idx`, floats `3i .. 3i + 4`
/// of `base` must be readable.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn load_transposed(base: *const f32, idx: &[u32], pk: &mut [[f32; LANES]; 3]) {
    use std::arch::x86_64::*;
    // SAFETY: the function's contract; `idx` has 8 entries (indexed).
    let pair = |a: usize, b: usize| unsafe {
        _mm256_loadu2_m128(base.add(3 * idx[b] as usize), base.add(3 * idx[a] as usize))
    };
    // Register r holds points r (low half) and r + 4 (high half).
    let (a, b, c, d) = (pair(0, 4), pair(1, 5), pair(2, 6), pair(3, 7));
    let t0 = _mm256_unpacklo_ps(a, b);
    let t1 = _mm256_unpackhi_ps(a, b);
    let t2 = _mm256_unpacklo_ps(c, d);
    let t3 = _mm256_unpackhi_ps(c, d);
    // SAFETY: each `pk[c]` is 8 contiguous f32.
    unsafe {
        _mm256_storeu_ps(pk[0].as_mut_ptr(), _mm256_shuffle_ps::<0x44>(t0, t2));
        _mm256_storeu_ps(pk[1].as_mut_ptr(), _mm256_shuffle_ps::<0xEE>(t0, t2));
        _mm256_storeu_ps(pk[2].as_mut_ptr(), _mm256_shuffle_ps::<0x44>(t1, t3));
    }
}

/// `Vec3` is three packed f32 (the AVX2 copy writes outputs as floats).
const _: () = assert!(std::mem::size_of::<Vec3>() == 12);

/// Most rows of a smooth vertex the flat path takes (`3·MAX_VALENCE + 1`
/// for the built-in schemes, with room; `3·MAX_ROWS` is a multiple of 8).
const MAX_ROWS: usize = 4 * crate::kernels::common::MAX_VALENCE as usize + 8;
const _: () = assert!((3 * MAX_ROWS / LANES) * LANES == 3 * MAX_ROWS);

/// Rows 8 consecutive floats of 8 lanes each, transposed: register `l`
/// holds lane `l`'s 8 floats.
///
/// # Safety
/// AVX2 must be available.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn transpose8(r: &[[f32; LANES]]) -> [std::arch::x86_64::__m256; LANES] {
    use std::arch::x86_64::*;
    // SAFETY: each row is 8 contiguous f32; `r` has 8 rows (indexed).
    let l = |i: usize| unsafe { _mm256_loadu_ps(r[i].as_ptr()) };
    let (r0, r1, r2, r3, r4, r5, r6, r7) = (l(0), l(1), l(2), l(3), l(4), l(5), l(6), l(7));
    let t0 = _mm256_unpacklo_ps(r0, r1);
    let t1 = _mm256_unpackhi_ps(r0, r1);
    let t2 = _mm256_unpacklo_ps(r2, r3);
    let t3 = _mm256_unpackhi_ps(r2, r3);
    let t4 = _mm256_unpacklo_ps(r4, r5);
    let t5 = _mm256_unpackhi_ps(r4, r5);
    let t6 = _mm256_unpacklo_ps(r6, r7);
    let t7 = _mm256_unpackhi_ps(r6, r7);
    let u0 = _mm256_shuffle_ps::<0x44>(t0, t2);
    let u1 = _mm256_shuffle_ps::<0xEE>(t0, t2);
    let u2 = _mm256_shuffle_ps::<0x44>(t1, t3);
    let u3 = _mm256_shuffle_ps::<0xEE>(t1, t3);
    let u4 = _mm256_shuffle_ps::<0x44>(t4, t6);
    let u5 = _mm256_shuffle_ps::<0xEE>(t4, t6);
    let u6 = _mm256_shuffle_ps::<0x44>(t5, t7);
    let u7 = _mm256_shuffle_ps::<0xEE>(t5, t7);
    [
        _mm256_permute2f128_ps::<0x20>(u0, u4),
        _mm256_permute2f128_ps::<0x20>(u1, u5),
        _mm256_permute2f128_ps::<0x20>(u2, u6),
        _mm256_permute2f128_ps::<0x20>(u3, u7),
        _mm256_permute2f128_ps::<0x31>(u0, u4),
        _mm256_permute2f128_ps::<0x31>(u1, u5),
        _mm256_permute2f128_ps::<0x31>(u2, u6),
        _mm256_permute2f128_ps::<0x31>(u3, u7),
    ]
}

/// The lane buffers of [`FlatVertexStage::block`], made once per parallel
/// task rather than per block (clearing them per block cost ~9 % of the
/// stage's instructions). Every value read is written first in the same
/// chunk, except padding floats that are never stored.
pub(crate) struct Scratch {
    p: Lanes,
    acc: [[[f32; LANES]; 3]; MAX_ROWS],
}

impl Scratch {
    pub(crate) fn new() -> Box<Scratch> {
        Box::new(Scratch {
            p: [[[0.0f32; LANES]; 3]; MAX_SLOTS],
            acc: [[[0.0f32; LANES]; 3]; MAX_ROWS],
        })
    }
}

/// Gathered ring points: `[slot][component][lane]`.
type Lanes = [[[f32; LANES]; 3]; MAX_SLOTS];

/// One row's sums for every lane into `s`: from zero as the generated sum
/// starts (`0.0 + x` turns a -0.0 first term into +0.0), then per term in
/// slot order one multiply and one add per component and lane.
#[inline(always)]
fn row_baseline(terms: &[Term], p: &Lanes, s: &mut [[f32; LANES]; 3]) {
    *s = [[0.0f32; LANES]; 3];
    for t in terms {
        let pk = &p[t.slot as usize];
        for (sc, pc) in s.iter_mut().zip(pk) {
            for (x, &y) in sc.iter_mut().zip(pc) {
                *x += y * t.weight;
            }
        }
    }
}

/// [`row_baseline`] in AVX2 registers (one per component), written out
/// with intrinsics: left to itself LLVM vectorised the loop towards the
/// output's `Vec3` layout, with a shuffle per lane pair and term. The same
/// IEEE `×` then `+` per lane (no FMA: `avx2` does not enable it and these
/// are the separate `mul`/`add` instructions).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn row_avx2(terms: &[Term], p: &Lanes, s: &mut [[f32; LANES]; 3]) {
    use std::arch::x86_64::*;
    let (mut x, mut y, mut z) = (
        _mm256_setzero_ps(),
        _mm256_setzero_ps(),
        _mm256_setzero_ps(),
    );
    for t in terms {
        let pk = &p[t.slot as usize];
        let w = _mm256_set1_ps(t.weight);
        // SAFETY: each `pk[c]` is 8 contiguous f32 (unaligned loads).
        unsafe {
            x = _mm256_add_ps(x, _mm256_mul_ps(_mm256_loadu_ps(pk[0].as_ptr()), w));
            y = _mm256_add_ps(y, _mm256_mul_ps(_mm256_loadu_ps(pk[1].as_ptr()), w));
            z = _mm256_add_ps(z, _mm256_mul_ps(_mm256_loadu_ps(pk[2].as_ptr()), w));
        }
    }
    // SAFETY: each `s[c]` is 8 contiguous f32.
    unsafe {
        _mm256_storeu_ps(s[0].as_mut_ptr(), x);
        _mm256_storeu_ps(s[1].as_mut_ptr(), y);
        _mm256_storeu_ps(s[2].as_mut_ptr(), z);
    }
}

/// A vertex without sectors (the generated kernel's smooth branch).
fn smooth(topo: &Topology, v: usize) -> bool {
    topo.vertex_sectors.get(v) == topo.vertex_sectors.get(v + 1)
}

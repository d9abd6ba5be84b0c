// osd_bench.cpp -- single-thread OpenSubdiv 3.6 CPU baseline for tessgen's CPU bench.
//
// Links OpenSubdiv (Modified Apache 2.0); this harness is our own code.
//
// Input: an OBJ of quads (v / f lines; "f a/b/c" forms accepted). Catmull-Clark,
// vertex boundary interpolation EDGE_ONLY. For each base face and each level N,
// (N+1)x(N+1) samples at u=i/N, v=j/N; per sample position and unit normal
// normalize(cross(dPdu, dPdv)) are written to preallocated, pre-touched float
// arrays (positions: 3 floats/sample, normals: 3 floats/sample, i.e. 24 B/sample,
// the same layout as tessgen's Vec3 positions + Vec3 normals).
//
// Modes (--modes, comma separated):
//   far:L:E   Far adaptive PatchTable, isolation level L, end caps E
//             (gregory = ENDCAP_GREGORY_BASIS (OSD's default) or bspline = ENDCAP_BSPLINE_BASIS).
//             Per sample: PatchMap::FindPatch -> PatchTable::EvaluateBasis ->
//             sum over GetPatchVertices of [refined vertices | local points].
//             Also times the per-deformation update (StencilTable::UpdateValues
//             over a stencil table of all refined vertices + local points, and
//             alternatively PrimvarRefiner::Interpolate + local-point stencils).
//   bfr       Bfr::RefinerSurfaceFactory (default options: caching on,
//             approxLevelSmooth 2, approxLevelSharp 6) over the unrefined
//             refiner; per face InitVertexSurface + PreparePatchPoints (timed),
//             then Surface::Evaluate(uv, P, Du, Dv) per sample.
//
// Timing: std::chrono::steady_clock around the evaluation loop only; minimum over
// --runs timed runs after one warm-up run (construction: --cruns runs).

#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/version.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>
#include <sys/resource.h>

using namespace OpenSubdiv;

#define OSD_STR2(x) #x
#define OSD_STR(x) OSD_STR2(x)

// ---------------------------------------------------------------------------
struct Mesh {
    std::vector<float> pos;      // 3 per vertex
    std::vector<int> faceSizes;
    std::vector<int> faceVerts;
    int numVerts() const { return (int)pos.size() / 3; }
    int numFaces() const { return (int)faceSizes.size(); }
};

static Mesh loadObj(const char *path) {
    std::ifstream in(path);
    if (!in) { fprintf(stderr, "cannot open %s\n", path); exit(1); }
    Mesh m;
    std::string line;
    while (std::getline(in, line)) {
        if (line.size() < 2) continue;
        if (line[0] == 'v' && (line[1] == ' ' || line[1] == '\t')) {
            float x, y, z;
            if (sscanf(line.c_str() + 2, "%f %f %f", &x, &y, &z) != 3) {
                fprintf(stderr, "bad v line: %s\n", line.c_str()); exit(1);
            }
            m.pos.push_back(x); m.pos.push_back(y); m.pos.push_back(z);
        } else if (line[0] == 'f' && (line[1] == ' ' || line[1] == '\t')) {
            std::istringstream ss(line.substr(2));
            std::string tok;
            int n = 0;
            while (ss >> tok) {
                int idx = atoi(tok.c_str());  // stops at '/': "a/b/c" -> a
                if (idx < 0) idx = m.numVerts() + idx; else idx -= 1;
                m.faceVerts.push_back(idx);
                ++n;
            }
            m.faceSizes.push_back(n);
        }
    }
    return m;
}

static Far::TopologyRefiner *createRefiner(const Mesh &m) {
    typedef Far::TopologyDescriptor Desc;
    Sdc::Options sdcOpts;
    sdcOpts.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    Desc desc;
    desc.numVertices = m.numVerts();
    desc.numFaces = m.numFaces();
    desc.numVertsPerFace = m.faceSizes.data();
    desc.vertIndicesPerFace = m.faceVerts.data();
    Far::TopologyRefiner *r = Far::TopologyRefinerFactory<Desc>::Create(
        desc, Far::TopologyRefinerFactory<Desc>::Options(Sdc::SCHEME_CATMARK, sdcOpts));
    if (!r) { fprintf(stderr, "TopologyRefinerFactory::Create failed\n"); exit(1); }
    return r;
}

// ---------------------------------------------------------------------------
struct V3 {
    float p[3];
    void Clear(void * = 0) { p[0] = p[1] = p[2] = 0.0f; }
    void AddWithWeight(V3 const &s, float w) {
        p[0] += w * s.p[0]; p[1] += w * s.p[1]; p[2] += w * s.p[2];
    }
};

typedef std::chrono::steady_clock Clock;
static double secs(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

// Involuntary context switches (preemptions) during the fastest run and during all timed runs of the
// last minTime call: a fastest run with 0 was not preempted by another process on this CPU.
static long g_ivcswBest = 0, g_ivcswAll = 0;
static long ivcsw() {
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_nivcsw;
}

template <class F> static double minTime(int runs, F f) {
    f();  // warm-up
    double best = std::numeric_limits<double>::infinity();
    g_ivcswAll = 0;
    for (int r = 0; r < runs; ++r) {
        long c0 = ivcsw();
        Clock::time_point t0 = Clock::now();
        f();
        double t = secs(t0, Clock::now());
        long c = ivcsw() - c0;
        g_ivcswAll += c;
        if (t < best) { best = t; g_ivcswBest = c; }
    }
    return best;
}

static inline void storeNormal(const float du[3], const float dv[3], float *n) {
    float x = du[1] * dv[2] - du[2] * dv[1];
    float y = du[2] * dv[0] - du[0] * dv[2];
    float z = du[0] * dv[1] - du[1] * dv[0];
    float inv = 1.0f / std::sqrt(x * x + y * y + z * z);
    n[0] = x * inv; n[1] = y * inv; n[2] = z * inv;
}

struct Output {
    std::vector<float> P, N;
};

// Sanity statistics of one evaluation's output (not timed).
static void sanity(const char *tag, int level, const Output &o, const Mesh &m,
                   const std::vector<float> *ref, const std::vector<float> *refN) {
    size_t S = o.P.size() / 3;
    double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30};
    double blo[3] = {1e30, 1e30, 1e30}, bhi[3] = {-1e30, -1e30, -1e30};
    size_t nanP = 0, nanN = 0;
    double maxDevN = 0, sumDevN = 0;
    for (size_t s = 0; s < S; ++s) {
        const float *p = &o.P[3 * s], *n = &o.N[3 * s];
        if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))) { ++nanP; continue; }
        for (int k = 0; k < 3; ++k) { lo[k] = std::min(lo[k], (double)p[k]); hi[k] = std::max(hi[k], (double)p[k]); }
        if (!(std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2]))) { ++nanN; continue; }
        double len = std::sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        maxDevN = std::max(maxDevN, std::fabs(len - 1.0));
        sumDevN += std::fabs(len - 1.0);
    }
    for (int v = 0; v < m.numVerts(); ++v)
        for (int k = 0; k < 3; ++k) {
            blo[k] = std::min(blo[k], (double)m.pos[3 * v + k]);
            bhi[k] = std::max(bhi[k], (double)m.pos[3 * v + k]);
        }
    printf("  sanity %s N=%d: samples bbox [%.6f %.6f %.6f]..[%.6f %.6f %.6f]; base bbox [%.6f %.6f %.6f]..[%.6f %.6f %.6f]\n",
           tag, level, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], blo[0], blo[1], blo[2], bhi[0], bhi[1], bhi[2]);
    bool inside = true;
    for (int k = 0; k < 3; ++k) inside = inside && lo[k] >= blo[k] - 1e-6 && hi[k] <= bhi[k] + 1e-6;
    printf("  sanity %s N=%d: samples bbox inside base bbox: %s; non-finite positions %zu, non-finite normals %zu; |len(n)-1| max %.3g mean %.3g\n",
           tag, level, inside ? "yes" : "NO", nanP, nanN, maxDevN, sumDevN / std::max<size_t>(1, S));
    {
        // Orientation: sample normal vs the geometric normal of its base quad (cross of the diagonals).
        size_t per = S / m.numFaces(), flipped = 0;
        for (size_t s = 0; s < S; ++s) {
            const int *fv = &m.faceVerts[4 * (s / per)];
            const float *a = &m.pos[3 * fv[0]], *b = &m.pos[3 * fv[1]], *c = &m.pos[3 * fv[2]], *d = &m.pos[3 * fv[3]];
            double e1[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, e2[3] = {d[0] - b[0], d[1] - b[1], d[2] - b[2]};
            double g[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
            const float *n = &o.N[3 * s];
            if (g[0] * n[0] + g[1] * n[1] + g[2] * n[2] <= 0) ++flipped;
        }
        printf("  sanity %s N=%d: samples whose normal points away from their base quad's normal: %zu of %zu\n", tag, level,
               flipped, S);
    }
    if (ref) {
        double maxD = 0, sumD = 0;
        for (size_t s = 0; s < S; ++s) {
            double dx = o.P[3 * s] - (*ref)[3 * s], dy = o.P[3 * s + 1] - (*ref)[3 * s + 1],
                   dz = o.P[3 * s + 2] - (*ref)[3 * s + 2];
            double d = std::sqrt(dx * dx + dy * dy + dz * dz);
            if (std::isfinite(d)) { maxD = std::max(maxD, d); sumD += d; }
        }
        double diag = std::sqrt((bhi[0] - blo[0]) * (bhi[0] - blo[0]) + (bhi[1] - blo[1]) * (bhi[1] - blo[1]) +
                                (bhi[2] - blo[2]) * (bhi[2] - blo[2]));
        printf("  sanity %s N=%d: distance to first mode's positions: max %.3g mean %.3g (base bbox diagonal %.4f)\n",
               tag, level, maxD, sumD / std::max<size_t>(1, S), diag);
    }
    if (refN) {
        double maxA = 0, sumA = 0;
        for (size_t s = 0; s < S; ++s) {
            double d = (double)o.N[3 * s] * (*refN)[3 * s] + (double)o.N[3 * s + 1] * (*refN)[3 * s + 1] +
                       (double)o.N[3 * s + 2] * (*refN)[3 * s + 2];
            double a = std::acos(std::max(-1.0, std::min(1.0, d))) * 180.0 / M_PI;
            if (std::isfinite(a)) { maxA = std::max(maxA, a); sumA += a; }
        }
        printf("  sanity %s N=%d: angle to first mode's normals: max %.3g deg mean %.3g deg\n", tag, level, maxA,
               sumA / std::max<size_t>(1, S));
    }
}

// ---------------------------------------------------------------------------
// Far PatchTable mode
struct FarSetup {
    Far::TopologyRefiner *refiner = nullptr;
    Far::PatchTable *patchTable = nullptr;
    Far::PatchMap *patchMap = nullptr;
    Far::StencilTable const *allStencils = nullptr;  // refined (levels >= 1) + local points, factorized
    std::vector<V3> verts;                           // [coarse | refined levels 1.. | local points]
    int nCoarse = 0, nRefinedTotal = 0, nLocal = 0;
};

static const char *endCapName(int e) {
    switch (e) {
    case Far::PatchTableFactory::Options::ENDCAP_BILINEAR_BASIS: return "bilinear";
    case Far::PatchTableFactory::Options::ENDCAP_BSPLINE_BASIS: return "bspline";
    case Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS: return "gregory";
    case Far::PatchTableFactory::Options::ENDCAP_LEGACY_GREGORY: return "legacy";
    default: return "none";
    }
}

static void runFar(const Mesh &m, int isoLevel, Far::PatchTableFactory::Options::EndCapType endCap,
                   const std::vector<int> &levels, int runs, int cruns, bool check,
                   std::vector<std::vector<float>> &refs, std::vector<std::vector<float>> &refsN, bool firstMode) {
    printf("\n== mode far: adaptive isolation level %d, end caps %s ==\n", isoLevel, endCapName(endCap));
    {
        Far::PatchTableFactory::Options dflt;
        printf("  (PatchTableFactory::Options default end cap type: %s)\n", endCapName(dflt.GetEndCapType()));
    }
    FarSetup fs;
    Clock::time_point t0 = Clock::now();
    fs.refiner = createRefiner(m);
    Clock::time_point t1 = Clock::now();
    Far::PatchTableFactory::Options po(isoLevel);
    po.SetEndCapType(endCap);
    po.generateVaryingTables = false;
    fs.refiner->RefineAdaptive(po.GetRefineAdaptiveOptions());
    Clock::time_point t2 = Clock::now();
    fs.patchTable = Far::PatchTableFactory::Create(*fs.refiner, po);
    Clock::time_point t3 = Clock::now();
    fs.patchMap = new Far::PatchMap(*fs.patchTable);
    Clock::time_point t4 = Clock::now();
    Far::StencilTableFactory::Options so;
    so.generateIntermediateLevels = true;
    so.factorizeIntermediateLevels = true;
    so.generateControlVerts = false;
    so.generateOffsets = true;
    Far::StencilTable const *base = Far::StencilTableFactory::Create(*fs.refiner, so);
    Far::StencilTable const *lp = fs.patchTable->GetLocalPointStencilTable();
    if (lp && lp->GetNumStencils() > 0) {
        fs.allStencils = Far::StencilTableFactory::AppendLocalPointStencilTable(*fs.refiner, base, lp);
    } else {
        fs.allStencils = base;
    }
    Clock::time_point t5 = Clock::now();

    fs.nCoarse = fs.refiner->GetLevel(0).GetNumVertices();
    fs.nRefinedTotal = fs.refiner->GetNumVerticesTotal();
    fs.nLocal = fs.patchTable->GetNumLocalPoints();
    fs.verts.resize(fs.nRefinedTotal + fs.nLocal);
    int expectStencils = fs.nRefinedTotal - fs.nCoarse + fs.nLocal;
    printf("  refiner levels %d, vertices total %d (coarse %d), local points %d, stencils %d (expected %d), stencil weights %zu\n",
           fs.refiner->GetNumLevels(), fs.nRefinedTotal, fs.nCoarse, fs.nLocal,
           fs.allStencils->GetNumStencils(), expectStencils, fs.allStencils->GetControlIndices().size());
    if (fs.allStencils->GetNumStencils() != expectStencils) { fprintf(stderr, "stencil count mismatch\n"); exit(1); }
    {
        printf("  patches:");
        int total = 0;
        for (int a = 0; a < fs.patchTable->GetNumPatchArrays(); ++a) {
            Far::PatchDescriptor d = fs.patchTable->GetPatchArrayDescriptor(a);
            int np = fs.patchTable->GetNumPatches(a);
            total += np;
            printf(" %d x type %d (%d CVs)", np, (int)d.GetType(), d.GetNumControlVertices());
        }
        printf("; total %d (types: 6=REGULAR, 9=GREGORY_BASIS)\n", total);
    }
    printf("  setup (one-off, topology only): create refiner %.1f ms, RefineAdaptive %.1f ms, PatchTableFactory %.1f ms, PatchMap %.1f ms, StencilTableFactory+Append %.1f ms\n",
           secs(t0, t1) * 1e3, secs(t1, t2) * 1e3, secs(t2, t3) * 1e3, secs(t3, t4) * 1e3, secs(t4, t5) * 1e3);

    // (c) per-deformation construction.
    const V3 *coarse = reinterpret_cast<const V3 *>(m.pos.data());
    V3 *vb = fs.verts.data();
    Far::StencilTable const *allSt = fs.allStencils;
    int nC = fs.nCoarse;
    auto updStencil = [&]() {
        std::memcpy(vb, coarse, sizeof(V3) * nC);
        allSt->UpdateValues(vb, vb + nC);
    };
    double tSt = minTime(cruns, updStencil);
    std::vector<V3> viaStencil = fs.verts;

    Far::PrimvarRefiner pr(*fs.refiner);
    Far::TopologyRefiner const *rr = fs.refiner;
    int nTot = fs.nRefinedTotal;
    auto interpOnly = [&]() {
        std::memcpy(vb, coarse, sizeof(V3) * nC);
        V3 *src = vb;
        for (int lv = 1; lv < rr->GetNumLevels(); ++lv) {
            V3 *dst = src + rr->GetLevel(lv - 1).GetNumVertices();
            pr.Interpolate(lv, src, dst);
            src = dst;
        }
    };
    auto updPrimvar = [&]() {
        interpOnly();
        if (lp && lp->GetNumStencils() > 0) lp->UpdateValues(vb, vb + nTot);
    };
    double tPrInterp = minTime(cruns, interpOnly);
    double tPr = minTime(cruns, updPrimvar);
    double maxDiff = 0;
    for (size_t i = 0; i < fs.verts.size(); ++i)
        for (int k = 0; k < 3; ++k)
            maxDiff = std::max(maxDiff, (double)std::fabs(fs.verts[i].p[k] - viaStencil[i].p[k]));
    printf("  construction per deformation (min of %d): StencilTable::UpdateValues (refined+local, factorized; incl. %d-vertex memcpy) %.3f ms; "
           "PrimvarRefiner::Interpolate levels 1..%d alone %.3f ms; PrimvarRefiner + local-point StencilTable::UpdateValues %.3f ms; max |diff| between the two %.3g\n",
           cruns, nC, tSt * 1e3, fs.refiner->GetNumLevels() - 1, tPrInterp * 1e3, tPr * 1e3, maxDiff);
    printf("RESULT far L%d %s construct_stencil_ms %.4f construct_primvar_ms %.4f primvar_interp_only_ms %.4f\n",
           isoLevel, endCapName(endCap), tSt * 1e3, tPr * 1e3, tPrInterp * 1e3);
    fs.verts = viaStencil;

    // (a) evaluation.
    const int nFaces = m.numFaces();
    for (size_t li = 0; li < levels.size(); ++li) {
        int N = levels[li];
        const int per = (N + 1) * (N + 1);
        size_t S = (size_t)nFaces * per;
        Output o;
        o.P.assign(3 * S, 0.0f);  // allocated and touched outside timing
        o.N.assign(3 * S, 0.0f);
        float *outP = o.P.data(), *outN = o.N.data();
        const Far::PatchTable *pt = fs.patchTable;
        const Far::PatchMap *pm = fs.patchMap;
        const V3 *cv = fs.verts.data();
        const float inv = 1.0f / (float)N;
        auto eval = [&]() {
            float wP[20], wDu[20], wDv[20];
            size_t s = 0;
            for (int f = 0; f < nFaces; ++f) {
                for (int j = 0; j <= N; ++j) {
                    float v = (float)j * inv;
                    for (int i = 0; i <= N; ++i, ++s) {
                        float u = (float)i * inv;
                        Far::PatchTable::PatchHandle const *h = pm->FindPatch(f, u, v);
                        pt->EvaluateBasis(*h, u, v, wP, wDu, wDv);
                        Far::ConstIndexArray cvs = pt->GetPatchVertices(*h);
                        float P[3] = {0, 0, 0}, Du[3] = {0, 0, 0}, Dv[3] = {0, 0, 0};
                        for (int c = 0; c < cvs.size(); ++c) {
                            const float *x = cv[cvs[c]].p;
                            float a = wP[c], b = wDu[c], d = wDv[c];
                            P[0] += a * x[0]; P[1] += a * x[1]; P[2] += a * x[2];
                            Du[0] += b * x[0]; Du[1] += b * x[1]; Du[2] += b * x[2];
                            Dv[0] += d * x[0]; Dv[1] += d * x[1]; Dv[2] += d * x[2];
                        }
                        float *op = outP + 3 * s;
                        op[0] = P[0]; op[1] = P[1]; op[2] = P[2];
                        storeNormal(Du, Dv, outN + 3 * s);
                    }
                }
            }
        };
        double t = minTime(runs, eval);
        printf("  far L%d %s N=%d samples %zu: evaluate %.3f ms, %.2f ns/sample (min of %d after 1 warm-up; preemptions in fastest run %ld, in all runs %ld)\n",
               isoLevel, endCapName(endCap), N, S, t * 1e3, t * 1e9 / S, runs, g_ivcswBest, g_ivcswAll);
        printf("RESULT far L%d %s N %d samples %zu ns_per_sample %.3f ms %.3f ivcsw_best %ld ivcsw_all %ld\n", isoLevel,
               endCapName(endCap), N, S, t * 1e9 / S, t * 1e3, g_ivcswBest, g_ivcswAll);
        if (check) {
            bool useRef = !firstMode && refs[li].size() == o.P.size();
            char tag[64];
            snprintf(tag, sizeof tag, "far-L%d-%s", isoLevel, endCapName(endCap));
            sanity(tag, N, o, m, useRef ? &refs[li] : nullptr, useRef ? &refsN[li] : nullptr);
            if (firstMode) { refs[li] = o.P; refsN[li] = o.N; }
        }
    }
    delete fs.patchMap;
    delete fs.patchTable;
    if (fs.allStencils != base) delete fs.allStencils;
    delete base;
    delete fs.refiner;
}

// ---------------------------------------------------------------------------
// Bfr mode
static void runBfr(const Mesh &m, const std::vector<int> &levels, int runs, bool check,
                   std::vector<std::vector<float>> &refs, std::vector<std::vector<float>> &refsN, bool firstMode) {
    typedef Bfr::RefinerSurfaceFactory<> Factory;
    typedef Bfr::Surface<float> Surface;
    Factory::Options fo;  // defaults
    printf("\n== mode bfr: RefinerSurfaceFactory, caching %s, approxLevelSmooth %d, approxLevelSharp %d ==\n",
           fo.IsCachingEnabled() ? "on" : "off", fo.GetApproxLevelSmooth(), fo.GetApproxLevelSharp());
    Far::TopologyRefiner *r = createRefiner(m);
    Factory factory(*r, fo);
    const int nFaces = m.numFaces();
    {
        // Classify faces (not timed).
        Surface s;
        int reg = 0, lin = 0, irr = 0, bad = 0, maxPP = 0;
        for (int f = 0; f < nFaces; ++f) {
            if (!factory.InitVertexSurface<float>(f, &s)) { ++bad; continue; }
            if (s.IsRegular()) ++reg; else if (s.IsLinear()) ++lin; else ++irr;
            maxPP = std::max(maxPP, s.GetNumPatchPoints());
        }
        printf("  faces: %d regular, %d irregular (patch tree), %d linear, %d without surface; max patch points %d\n",
               reg, irr, lin, bad, maxPP);
    }
    const float *meshP = m.pos.data();
    Surface::PointDescriptor pd(3);
    {
        // Diagnostic: the per-face part alone (InitVertexSurface + PreparePatchPoints), same loop without samples.
        Surface surf;
        std::vector<float> patchPts(3 * 128);
        volatile float sink = 0;
        double t = minTime(runs, [&]() {
            float acc = 0;
            for (int f = 0; f < nFaces; ++f) {
                if (!factory.InitVertexSurface<float>(f, &surf)) continue;
                size_t need = 3 * (size_t)surf.GetNumPatchPoints();
                if (need > patchPts.size()) patchPts.resize(need);
                surf.PreparePatchPoints(meshP, pd, patchPts.data(), pd);
                acc += patchPts[0];
            }
            sink = acc;
        });
        (void)sink;
        printf("  bfr per-face part alone (InitVertexSurface + PreparePatchPoints over all %d faces): %.3f ms (%.1f ns/face)\n",
               nFaces, t * 1e3, t * 1e9 / nFaces);
        printf("RESULT bfr perface_ms %.4f\n", t * 1e3);
    }
    for (size_t li = 0; li < levels.size(); ++li) {
        int N = levels[li];
        const int per = (N + 1) * (N + 1);
        size_t S = (size_t)nFaces * per;
        Output o;
        o.P.assign(3 * S, 0.0f);
        o.N.assign(3 * S, 0.0f);
        float *outP = o.P.data(), *outN = o.N.data();
        std::vector<float> patchPts(3 * 64);
        const float inv = 1.0f / (float)N;
        Surface surf;
        auto eval = [&]() {
            size_t s = 0;
            for (int f = 0; f < nFaces; ++f) {
                if (!factory.InitVertexSurface<float>(f, &surf)) { s += per; continue; }
                size_t need = 3 * (size_t)surf.GetNumPatchPoints();
                if (need > patchPts.size()) patchPts.resize(need);
                surf.PreparePatchPoints(meshP, pd, patchPts.data(), pd);
                const float *pp = patchPts.data();
                for (int j = 0; j <= N; ++j) {
                    for (int i = 0; i <= N; ++i, ++s) {
                        float uv[2] = {(float)i * inv, (float)j * inv};
                        float Du[3], Dv[3];
                        surf.Evaluate(uv, pp, pd, outP + 3 * s, Du, Dv);
                        storeNormal(Du, Dv, outN + 3 * s);
                    }
                }
            }
        };
        double t = minTime(runs, eval);
        printf("  bfr N=%d samples %zu: evaluate %.3f ms, %.2f ns/sample (min of %d after 1 warm-up; preemptions in fastest run %ld, in all runs %ld)\n",
               N, S, t * 1e3, t * 1e9 / S, runs, g_ivcswBest, g_ivcswAll);
        printf("RESULT bfr N %d samples %zu ns_per_sample %.3f ms %.3f ivcsw_best %ld ivcsw_all %ld\n", N, S, t * 1e9 / S,
               t * 1e3, g_ivcswBest, g_ivcswAll);
        if (check) {
            bool useRef = !firstMode && refs[li].size() == o.P.size();
            sanity("bfr", N, o, m, useRef ? &refs[li] : nullptr, useRef ? &refsN[li] : nullptr);
            if (firstMode) { refs[li] = o.P; refsN[li] = o.N; }
        }
    }
    delete r;
}

// ---------------------------------------------------------------------------
static std::vector<std::string> split(const std::string &s, char c) {
    std::vector<std::string> out;
    std::string cur;
    for (char ch : s) {
        if (ch == c) { out.push_back(cur); cur.clear(); } else cur += ch;
    }
    if (!cur.empty()) out.push_back(cur);
    return out;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s MESH.obj [--levels 9,17,33] [--runs 7] [--cruns 15] "
                        "[--modes far:2:gregory,far:3:gregory,bfr] [--no-check]\n", argv[0]);
        return 2;
    }
    const char *meshPath = argv[1];
    std::vector<int> levels = {9, 17, 33};
    int runs = 7, cruns = 15;
    bool check = true;
    std::string modes = "far:2:gregory,far:3:gregory,bfr";
    for (int a = 2; a < argc; ++a) {
        std::string k = argv[a];
        if (k == "--levels" && a + 1 < argc) {
            levels.clear();
            for (auto &t : split(argv[++a], ',')) levels.push_back(atoi(t.c_str()));
        } else if (k == "--runs" && a + 1 < argc) runs = atoi(argv[++a]);
        else if (k == "--cruns" && a + 1 < argc) cruns = atoi(argv[++a]);
        else if (k == "--modes" && a + 1 < argc) modes = argv[++a];
        else if (k == "--no-check") check = false;
        else { fprintf(stderr, "unknown arg %s\n", k.c_str()); return 2; }
    }
    Mesh m = loadObj(meshPath);
    int nonQuads = 0;
    for (int n : m.faceSizes) nonQuads += (n != 4);
    printf("OpenSubdiv %s (%d); mesh %s: %d vertices, %d faces (%d non-quad)\n", OSD_STR(OPENSUBDIV_VERSION),
           OPENSUBDIV_VERSION_NUMBER, meshPath, m.numVerts(), m.numFaces(), nonQuads);
    if (nonQuads) {
        fprintf(stderr, "non-quad faces: base face index != ptex index; not supported by this harness\n");
        return 1;
    }
    printf("single thread; levels");
    for (int l : levels) printf(" %d", l);
    printf("; eval runs %d (min, after 1 warm-up); construction runs %d\n", runs, cruns);

    std::vector<std::vector<float>> refs(levels.size()), refsN(levels.size());
    bool first = true;
    for (auto &md : split(modes, ',')) {
        auto parts = split(md, ':');
        if (parts[0] == "far") {
            int lv = parts.size() > 1 ? atoi(parts[1].c_str()) : 2;
            std::string ec = parts.size() > 2 ? parts[2] : "gregory";
            Far::PatchTableFactory::Options::EndCapType e = Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS;
            if (ec == "bspline") e = Far::PatchTableFactory::Options::ENDCAP_BSPLINE_BASIS;
            else if (ec != "gregory") { fprintf(stderr, "unknown end cap %s\n", ec.c_str()); return 2; }
            runFar(m, lv, e, levels, runs, cruns, check, refs, refsN, first);
        } else if (parts[0] == "bfr") {
            runBfr(m, levels, runs, check, refs, refsN, first);
        } else {
            fprintf(stderr, "unknown mode %s\n", md.c_str());
            return 2;
        }
        first = false;
        fflush(stdout);
    }
    return 0;
}

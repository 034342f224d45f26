// refineTextures: rank layouts by chart splitting + parameterize, and the MIP-style bakes.
//
// Pipeline of refineTextures, in execution order:
//   rankZero                  T0 as it is, measured over every level (measure.cpp) within the budget
//   per rank j:
//     nextSplit               the next finer level whose regions split rank j-1's charts: per
//                             parent chart, its faces as a small mesh with that level's regions,
//                             merged down to ~splitPerChart disks by buildCharts (splitCharts)
//     keepLevelTrianglesWhole (optional) fewer pieces where the split cuts level triangles
//     solveRankLayout         parameterize() with the split charts as the last level's regions
//                             (merging disabled, rankLayout); worse pieces are split again
//     trimServedLevels        the levels 0..v the rank serves, against T0 over the same levels
//   bakeHierarchy             every layout at every size with bakeBaseColor (original appearance)
#include <algorithm>
#include <exception>
#include <map>
#include <optional>
#include <unordered_map>
#include <utility>

#include "lodbake/atlas/atlas.h"
#include "lodbake/bake/bake.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/key_set.h"
#include "lodbake/core/parallel.h"
#include "lodbake/core/timing.h"
#include "lodbake/chart/charts.h"
#include "lodbake/chart/level_charts.h"
#include "lodbake/texture_hierarchy/refine.h"

namespace lodbake {
namespace {

uint32_t countRegions(const std::vector<uint32_t>& faceRegion) {
    std::vector<uint32_t> reps = faceRegion;
    std::sort(reps.begin(), reps.end());
    return uint32_t(std::unique(reps.begin(), reps.end()) - reps.begin());
}

// parameterize over levels 1..last with `charts` (faceRegion form) as the last level's regions and
// chart merging disabled; `layout` false stops once the charts are solved.
ParameterizeResult parameterizeRank(const TriMesh& mesh, const Multires& mr, uint32_t last, const std::vector<uint32_t>& charts,
                                    const RefineOptions& o, bool layout, RankResult& rr) {
    // Levels 1..last keep their pairs and triangles (guarded by the solver); for last = 0 a level
    // without geometry carries the charts.
    Multires sub;
    sub.levels.assign(mr.levels.begin(), mr.levels.begin() + last);
    if (last == 0) sub.levels.emplace_back();
    sub.levels.back().faceRegion = charts;
    sub.levels.back().regionCount = countRegions(charts);
    ParameterizeOptions po = o.param;
    // A level triangle that would fold in the rank's charts gets its own island, as in T0.
    po.levelIslands = true;
    po.charts = ChartOptions{};
    po.charts.maxCharts = 0;
    po.charts.maxRegionEnergy = 1e-300;  // refuse every merge: the split charts are final
    po.progress = nullptr;
    po.layout = layout;
    ParameterizeResult pr = parameterize(mesh, sub, po);
    rr.parameterizeSeconds += pr.seconds;
    return pr;
}

// The parent charts (ids of `parentChart`) whose pieces in `pr` came out worse than the parent:
// summed E above parentE[p] (r = 1), or a piece left at its Tutte map.
std::vector<uint32_t> worseParents(const TriMesh& mesh, const ParameterizeResult& pr, const RefineOptions& o,
                                   const std::vector<uint32_t>& parentChart, const std::vector<ChartEnergy>& parentE) {
    const double r = (512.0 * 512.0) / (double(o.param.textureSize) * o.param.textureSize);
    std::vector<double> childE(parentE.size(), 0);
    std::vector<char> tutte(parentE.size(), 0), counted(pr.charts.chartCount, 0);
    for (size_t f = 0; f < mesh.triangleCount(); ++f) {
        int32_t c = pr.charts.faceChart[f];
        if (c < 0 || counted[size_t(c)]) continue;
        counted[size_t(c)] = 1;
        childE[parentChart[f]] += pr.chartReports[size_t(c)].final.E / r;
        const ChartReport& cr = pr.chartReports[size_t(c)];
        if (cr.method == "tutte" && o.param.solve.maxIterations > 0) tutte[parentChart[f]] = 1;
    }
    std::vector<uint32_t> bad;
    for (uint32_t p = 0; p < parentE.size(); ++p)
        if (tutte[p] || childE[p] > parentE[p].E) bad.push_back(p);
    return bad;
}

// The rank-j layout of `charts`: parameterizeRank with the atlas.
// \throw SolverError when UV triangles of the original stay flipped or overlapping, Impossible
// when the charts do not fit the texture at any density.
ChartLayout rankLayout(const TriMesh& mesh, const Multires& mr, uint32_t last, const std::vector<uint32_t>& charts,
                       const RefineOptions& o, RankResult& rr) {
    ParameterizeResult pr = parameterizeRank(mesh, mr, last, charts, o, true, rr);
    rr.chartFlips = pr.flips;
    rr.chartOverlaps = pr.overlaps;
    rr.levelFlipsInSolve = pr.levelFlips;
    rr.methods.clear();
    for (const ChartReport& c : pr.chartReports) ++rr.methods[c.method];
    if (pr.flips > 0 || pr.overlaps > 0)
        throw SolverError("rank " + std::to_string(rr.rank) + ": " + std::to_string(pr.flips) + " flipped and " +
                          std::to_string(pr.overlaps) + " overlapping UV triangles");
    // parameterize lays out charts too many for the texture on a larger atlas (valid input must
    // not fail), but a rank only refines T0: such a rank ends the hierarchy.
    if (pr.atlasSize > o.param.textureSize)
        throw Impossible(std::to_string(pr.charts.chartCount) + " charts and " + std::to_string(pr.islands.size()) +
                         " level islands do not fit a " + std::to_string(o.param.textureSize) + " atlas at any density");
    ChartLayout lay;
    lay.chartCount = pr.charts.chartCount;
    lay.faceChart.resize(mesh.triangleCount());
    for (size_t f = 0; f < lay.faceChart.size(); ++f) lay.faceChart[f] = uint32_t(std::max(pr.charts.faceChart[f], 0));
    lay.cornerUV = pr.cornerUV;
    for (const LevelIsland& isl : pr.islands) lay.islands.push_back({isl.vertices, isl.uv});
    return lay;
}

// Level triangles of levels 1..last whose three corners are not all vertices of one chart (the
// chart levelTriangleCharts picks), counted per parent chart of their face. `faceChart` is either
// dense chart ids or, with `reps`, representative faces (splitCharts' form).
std::vector<size_t> crossingPerParent(const TriMesh& mesh, const Multires& mr, uint32_t last, std::vector<uint32_t> faceChart,
                                      bool reps, const std::vector<uint32_t>& parentChart, uint32_t parentCount) {
    uint32_t count = 0;
    if (reps) {
        std::unordered_map<uint32_t, uint32_t> dense;
        for (uint32_t& c : faceChart) c = dense.emplace(c, uint32_t(dense.size())).first->second;
        count = uint32_t(dense.size());
    } else {
        for (uint32_t c : faceChart) count = std::max(count, c + 1);
    }
    // Vertices of each chart.
    KeySet member(mesh.triangleCount());
    for (size_t f = 0; f < mesh.triangleCount(); ++f)
        for (uint32_t v : mesh.triangles[f]) member.insert((uint64_t(v) << 32) | faceChart[f]);
    std::vector<size_t> out(parentCount, 0);
    for (uint32_t l = 1; l <= last; ++l) {
        const Level& L = mr.levels[l - 1];
        std::vector<uint32_t> tc = levelTriangleCharts(mesh, faceChart, count, L);
        for (size_t t = 0; t < L.triangles.size(); ++t) {
            const Tri& v = L.triangles[t];
            if (degenerateIndices(v)) continue;
            for (uint32_t x : v)
                if (!member.contains((uint64_t(x) << 32) | tc[t])) {
                    ++out[parentChart[L.faces[t]]];
                    break;
                }
        }
    }
    return out;
}

}  // namespace

std::vector<uint32_t> splitCharts(const TriMesh& mesh, const std::vector<uint32_t>& parentChart, uint32_t parentCount,
                                  const std::vector<uint32_t>& faceRegion, uint32_t perChart, uint32_t& count) {
    return splitCharts(mesh, parentChart, parentCount, faceRegion, std::vector<uint32_t>(parentCount, perChart), count);
}

std::vector<uint32_t> splitCharts(const TriMesh& mesh, const std::vector<uint32_t>& parentChart, uint32_t parentCount,
                                  const std::vector<uint32_t>& faceRegion, const std::vector<uint32_t>& perChart,
                                  uint32_t& count) {
    return splitCharts(mesh, parentChart, parentCount, faceRegion, perChart, count, nullptr);
}

std::vector<uint32_t> splitCharts(const TriMesh& mesh, const std::vector<uint32_t>& parentChart, uint32_t parentCount,
                                  const std::vector<uint32_t>& faceRegion, const std::vector<uint32_t>& perChart,
                                  uint32_t& count, SplitMemo* memo, int threads) {
    const size_t nf = mesh.triangleCount();
    if (perChart.size() != parentCount) throw InvalidInput("splitCharts: perChart does not match the parent charts");
    if (parentChart.size() != nf || faceRegion.size() != nf) throw InvalidInput("splitCharts: tables do not match the mesh");
    std::vector<std::vector<uint32_t>> faces(parentCount);
    for (uint32_t f = 0; f < nf; ++f) {
        if (parentChart[f] >= parentCount || faceRegion[f] >= nf) throw InvalidInput("splitCharts: entry out of range");
        faces[parentChart[f]].push_back(f);
    }
    // The parents split anew (not in the memo; each parent's key is its own), each on its own:
    // the chart as its own mesh (compact vertices) with its part of every region, merged down by
    // buildCharts. Side by side on `threads` threads; errors as one after another.
    std::vector<uint32_t> todo;
    std::vector<size_t> todoIndex(parentCount, SIZE_MAX);
    for (uint32_t c = 0; c < parentCount; ++c)
        if (!faces[c].empty() && !(memo && memo->count({c, perChart[c]}))) {
            todoIndex[c] = todo.size();
            todo.push_back(c);
        }
    std::vector<ChartResult> split(todo.size());
    std::vector<std::exception_ptr> errors(todo.size());
    parallelFor(todo.size(), threads, [&](size_t k) {
        try {
            const uint32_t c = todo[k];
            const std::vector<uint32_t>& F = faces[c];
            TriMesh sub;
            std::unordered_map<uint32_t, uint32_t> vmap;
            std::map<uint32_t, uint32_t> regionRep;  // region representative -> first local face
            std::vector<uint32_t> localRegion(F.size());
            for (uint32_t i = 0; i < F.size(); ++i) {
                Tri t{};
                for (size_t j = 0; j < 3; ++j) {
                    auto [it, inserted] = vmap.emplace(mesh.triangles[F[i]][j], uint32_t(sub.positions.size()));
                    if (inserted) sub.positions.push_back(mesh.positions[mesh.triangles[F[i]][j]]);
                    t[j] = it->second;
                }
                sub.triangles.push_back(t);
                localRegion[i] = regionRep.emplace(faceRegion[F[i]], i).first->second;
            }
            ChartOptions co;
            co.maxCharts = std::max(1u, perChart[c]);
            split[k] = buildCharts(sub, localRegion, co);
        } catch (...) {
            errors[k] = std::current_exception();
        }
    });
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
    std::vector<uint32_t> out(nf);
    for (uint32_t f = 0; f < nf; ++f) out[f] = f;
    count = 0;
    for (uint32_t c = 0; c < parentCount; ++c) {
        const std::vector<uint32_t>& F = faces[c];
        if (F.empty()) continue;
        const std::pair<uint32_t, uint32_t> key{c, perChart[c]};
        if (todoIndex[c] == SIZE_MAX) {  // in the memo
            const auto& known = memo->at(key);
            for (uint32_t i = 0; i < F.size(); ++i) out[F[i]] = known.first[i];
            count += known.second;
            continue;
        }
        const uint32_t countBefore = count;
        const ChartResult& cr = split[todoIndex[c]];
        // Representative of each new chart: its smallest face (F is ascending).
        std::vector<uint32_t> rep(cr.chartCount, UINT32_MAX);
        for (uint32_t i = 0; i < F.size(); ++i) {
            int32_t s = cr.faceChart[i];
            if (s < 0) continue;
            if (rep[size_t(s)] == UINT32_MAX) {
                rep[size_t(s)] = F[i];
                ++count;
            }
            out[F[i]] = rep[size_t(s)];
        }
        // Faces buildCharts left out (index-degenerate) join the chart's first piece.
        for (uint32_t i = 0; i < F.size(); ++i)
            if (cr.faceChart[i] < 0) out[F[i]] = cr.chartCount > 0 && rep[0] != UINT32_MAX ? rep[0] : F[i];
        if (memo) {
            std::vector<uint32_t> pieces(F.size());
            for (uint32_t i = 0; i < F.size(); ++i) pieces[i] = out[F[i]];
            memo->emplace(key, std::make_pair(std::move(pieces), count - countBefore));
        }
    }
    return out;
}

namespace {

// \throw Impossible / InvalidInput as refineTextures documents.
void checkRefineInput(const Asset& asset, const Multires& mr, const RefineOptions& o) {
    const size_t nf = asset.mesh.triangleCount();
    if (nf == 0) throw Impossible(asset.sourcePath + ": no triangles");
    if (mr.charts.empty()) throw Impossible(asset.sourcePath + ": no chart layout (LODBAKE_multires charts); run parameterize first");
    if (mr.charts.faceChart.size() != nf || mr.charts.cornerUV.size() != nf)
        throw InvalidInput(asset.sourcePath + ": chart layout does not match the original mesh");
    for (const Level& L : mr.levels)
        if (L.faceRegion.size() != nf) throw InvalidInput(asset.sourcePath + ": level regions do not match the original mesh");
    if (o.sizes.empty()) throw InvalidInput("no texture sizes");
}

// T0's measure over levels 0..l: every candidate and rank compares against it. The first call
// (rankZero's, over every level) measures every l at once.
class BaseMeasures {
public:
    BaseMeasures(const TriMesh& mesh, const Multires& mr, const ChartEnergyOptions& eo, int threads)
        : mesh_(mesh), mr_(mr), eo_(eo), threads_(threads) {}
    const LayoutMeasure& upTo(uint32_t lastLevel) {
        if (lastLevel >= byLevel_.size()) byLevel_ = measureLayoutLevels(mesh_, mr_, mr_.charts, lastLevel, eo_, threads_);
        return byLevel_[lastLevel];
    }

private:
    const TriMesh& mesh_;
    const Multires& mr_;
    ChartEnergyOptions eo_;
    int threads_;
    std::vector<LayoutMeasure> byLevel_;  // index l: over levels 0..l
};

// Rank 0: T0 as it is, valid for every level; measured unless `measured` is false.
RankResult rankZero(const TriMesh& mesh, const Multires& mr, BaseMeasures& base, bool measured) {
    const uint32_t n = uint32_t(mr.levels.size());
    RankResult r0;
    r0.rank = 0;
    r0.lastLevel = n;
    r0.layout = mr.charts;
    r0.layout.material = -1;
    r0.measured = measured;
    if (measured) {
        r0.measure = base.upTo(n);
        r0.base = r0.measure;
    }
    r0.regions = n > 0 ? countRegions(mr.levels.back().faceRegion) : uint32_t(mesh.triangleCount());
    return r0;
}

// A candidate split of the parent layout's charts by the regions of one geometry level.
struct SplitCandidate {
    uint32_t level = 0;              // the level whose regions split the charts
    std::vector<uint32_t> regions;   // that level's faceRegion (level 0: every face its own region)
    std::vector<uint32_t> charts;    // the split charts (splitCharts' faceRegion form)
    uint32_t count = 0;              // how many
    SplitMemo memo;                  // the pieces of `regions` per (parent chart, target) made so far
};

// The coarsest level finer than `source` whose regions split the parent's charts into more
// charts (levels whose regions coincide with the coarser level's add nothing). count <= the
// parent's chart count when no level does.
SplitCandidate nextSplit(const TriMesh& mesh, const Multires& mr, const ChartLayout& parent, uint32_t source, uint32_t perChart,
                         int threads) {
    const size_t nf = mesh.triangleCount();
    SplitCandidate c;
    c.level = source;
    while (c.level > 0) {
        --c.level;
        if (c.level == 0) {
            c.regions.resize(nf);
            for (uint32_t f = 0; f < nf; ++f) c.regions[f] = f;
        } else {
            c.regions = mr.levels[c.level - 1].faceRegion;
        }
        c.memo.clear();
        c.charts = splitCharts(mesh, parent.faceChart, parent.chartCount, c.regions,
                               std::vector<uint32_t>(parent.chartCount, perChart), c.count, &c.memo, threads);
        if (c.count > parent.chartCount) break;
    }
    return c;
}

// Pieces whose new boundaries cut level triangles of the levels served (boundaries that are not
// p-boundaries there, e.g. from splitting a non-disk region) lose continuity where the parent had
// it: such parents are split into fewer pieces, down to keeping them whole (at most 3 rounds).
// Updates `per` (pieces per parent chart) and the candidate's charts.
void keepLevelTrianglesWhole(const TriMesh& mesh, const Multires& mr, const ChartLayout& parent, std::vector<uint32_t>& per,
                             SplitCandidate& cand, int threads) {
    const std::vector<size_t> parentCrossing =
        crossingPerParent(mesh, mr, cand.level, parent.faceChart, false, parent.faceChart, parent.chartCount);
    for (int round = 0; round < 3; ++round) {
        std::vector<size_t> crossing = crossingPerParent(mesh, mr, cand.level, cand.charts, true, parent.faceChart, parent.chartCount);
        bool changed = false;
        for (uint32_t p = 0; p < parent.chartCount; ++p)
            if (crossing[p] > parentCrossing[p] && per[p] > 1) {
                per[p] = round < 2 ? std::max(2u, per[p] / 2) : 1;
                changed = true;
            }
        if (!changed) break;
        cand.charts = splitCharts(mesh, parent.faceChart, parent.chartCount, cand.regions, per, cand.count, &cand.memo, threads);
    }
}

// Parameterises the candidate's charts; parents whose pieces came out worse than the parent are
// split again, finer (twice as many pieces) for two rounds and then not at all. Only the charts'
// solves decide a re-split, so the rounds before the last solve without an atlas; the last one's
// solves come from the candidate's solve cache and its atlas is the rank's layout.
// `parentIsT0`: the parent is rank 0 (T0 itself), whose measure `base` has.
void solveRankLayout(const TriMesh& mesh, const Multires& mr, const ChartLayout& parent, bool parentIsT0, const RefineOptions& o,
                     const ChartEnergyOptions& eo, BaseMeasures& base, std::vector<uint32_t>& per, SplitCandidate& cand,
                     RankResult& rr) {
    // The parent layout's own energy per chart over the levels this rank serves.
    const std::vector<ChartEnergy> parentE =
        parentIsT0 ? base.upTo(cand.level).chartEnergies : measureLayout(mesh, mr, parent, cand.level, eo, o.param.threads).chartEnergies;
    rr.parameterizeSeconds = 0;
    std::vector<uint32_t> bad;
    bool changed = true;
    for (int attempt = 0; attempt < 3; ++attempt) {
        // A re-split that left every chart as it was (its parents cannot be split finer) solves to
        // the same pieces: the same parents stay worse, without solving them again.
        if (changed) {
            const ParameterizeResult solved = parameterizeRank(mesh, mr, rr.lastLevel, cand.charts, o, false, rr);
            bad = worseParents(mesh, solved, o, parent.faceChart, parentE);
        }
        if (bad.empty()) break;
        for (uint32_t p : bad) per[p] = attempt < 2 ? per[p] * 2 : 1;
        std::vector<uint32_t> charts =
            splitCharts(mesh, parent.faceChart, parent.chartCount, cand.regions, per, cand.count, &cand.memo, o.param.threads);
        changed = charts != cand.charts;
        cand.charts = std::move(charts);
        ++rr.resplits;
    }
    rr.layout = rankLayout(mesh, mr, rr.lastLevel, cand.charts, o, rr);
    for (uint32_t p : per) rr.unsplit += p == 1 ? 1 : 0;
}

// Served levels: the longest run 0..v (v <= the level of its regions) on which the rank has no
// flipped and no overlapping level triangle (UVs as pack assigns them), its chart boundaries cut
// at most maxExtraCutFraction of the level's triangles more than T0's do (a cut triangle's corners
// outside its chart take projected UVs, which smear the texture; cut boundaries are not
// p-boundaries there), and, over 0..v, it lowers both E and the area-ratio std-dev of T0.
// Sets rr.lastLevel, rr.measure and rr.base; returns whether such a run exists.
bool trimServedLevels(const TriMesh& mesh, const Multires& mr, const RefineOptions& o, const ChartEnergyOptions& eo,
                      BaseMeasures& base, RankResult& rr) {
    std::vector<LayoutMeasure> byLevel = measureLayoutLevels(mesh, mr, rr.layout, rr.lastLevel, eo, o.param.threads);
    rr.measure = byLevel.back();
    rr.base = base.upTo(rr.lastLevel);
    auto serves = [&](uint32_t l) {
        const UVInjectivity& a = rr.measure.levels[l];
        const double extra = o.maxExtraCutFraction * double(a.triangles);
        return a.flips == 0 && a.overlaps == 0 && double(rr.measure.crossing[l]) <= double(rr.base.crossing[l]) + extra;
    };
    uint32_t valid = 0;
    while (valid < rr.lastLevel && serves(valid + 1)) ++valid;
    for (;;) {
        if (valid < rr.lastLevel) {
            rr.lastLevel = valid;
            rr.measure = byLevel[rr.lastLevel];
            rr.base = base.upTo(rr.lastLevel);
        }
        const bool better = rr.measure.energy.E < rr.base.energy.E && rr.measure.areaRatioStdDev < rr.base.areaRatioStdDev;
        if (better) return true;
        if (valid == 0) return false;
        --valid;
    }
}

// Every layout at every size (a rank >= 1 only at sizes >= minRefinedSize, and at the largest),
// baked from the original appearance unless o.bakeImages is false; `step` is called after each.
template <class Step>
void bakeHierarchy(const Asset& asset, const RefineOptions& o, RefineResult& res, Step&& step) {
    std::vector<int> sizes = o.sizes;
    std::sort(sizes.begin(), sizes.end());
    sizes.erase(std::unique(sizes.begin(), sizes.end()), sizes.end());
    std::optional<BakeSources> sources;  // the original images, decoded once for every bake
    if (o.bakeImages) sources.emplace(asset);
    for (const RankResult& rr : res.ranks) {
        // A layout's islands do not depend on the size: built once for all its bakes.
        std::vector<BakeIsland> islands;
        if (sources) islands = layoutBakeIslands(asset.mesh, rr.layout);
        for (int size : sizes) {
            if (rr.rank > 0 && size < o.minRefinedSize && size != sizes.back()) continue;
            RefinedImage img;
            img.rank = rr.rank;
            img.size = size;
            if (sources) {
                BakeOptions bo;
                bo.size = size;
                bo.threads = o.param.threads;
                BakeResult b = bakeBaseColor(*sources, rr.layout.cornerUV, bo, islands);
                img.image = std::move(b.image);
                img.image.name = "lodbake_T" + std::to_string(rr.rank) + "_" + std::to_string(size);
                img.coveredTexels = b.coveredTexels;
                img.seconds = b.seconds;
            }
            res.images.push_back(std::move(img));
            step();
        }
    }
}

}  // namespace

RefineResult refineTextures(const Asset& asset, const Multires& mr, const RefineOptions& options) {
    auto t0 = Clock::now();
    RefineOptions o = options;  // param.solveCache: one per candidate, below
    checkRefineInput(asset, mr, o);
    const TriMesh& mesh = asset.mesh;
    const uint32_t n = uint32_t(mr.levels.size());
    const bool overBudget = o.maxTriangles > 0 && mesh.triangleCount() > o.maxTriangles;
    const uint32_t maxRank = overBudget ? 0 : std::min<uint32_t>(uint32_t(std::max(0, o.ranks)), n);
    const double steps = double(maxRank + 1) * double(o.sizes.size()) + 2.0 * maxRank + 1;
    double done = 0;
    auto step = [&] { if (o.progress) o.progress(++done / steps); };

    ChartEnergyOptions eo;  // E at r = 1 with the rank layouts' alpha and beta
    eo.alpha = o.param.solve.energy.alpha;
    eo.beta = o.param.solve.energy.beta;
    RefineResult res;
    BaseMeasures base(mesh, mr, eo, o.param.threads);
    res.ranks.push_back(rankZero(mesh, mr, base, !overBudget));
    if (overBudget && o.ranks > 0 && n > 0)
        res.warnings.push_back(std::to_string(mesh.triangleCount()) + " triangles is over the budget of " +
                               std::to_string(o.maxTriangles) + " (--max-refine-triangles): no refined ranks, T0 serves every level");
    step();
    // Rank j splits rank j-1's charts by the regions of the next finer level that splits them; a
    // candidate is kept only when it lowers both E and the area-ratio spread of T0 over the levels
    // it serves, else the next finer level is tried.
    uint32_t source = n;
    for (uint32_t j = 1; j <= maxRank && source > 0;) {
        const ChartLayout& parent = res.ranks.back().layout;
        SplitCandidate cand = nextSplit(mesh, mr, parent, source, o.splitPerChart, o.param.threads);
        if (cand.count <= parent.chartCount) break;
        source = cand.level;
        if (base.upTo(cand.level).areaRatioStdDev < o.minAreaRatioStdDev) {
            res.rejected.push_back({cand.level, cand.count, "T0 is already near-isometric on these levels (area-ratio std-dev below the limit)"});
            continue;
        }
        RankResult rr;
        rr.rank = j;
        rr.lastLevel = cand.level;
        rr.regions = cand.level == 0 ? uint32_t(mesh.triangleCount()) : countRegions(mr.levels[cand.level - 1].faceRegion);
        std::vector<uint32_t> per(parent.chartCount, o.splitPerChart);
        if (o.keepLevelTrianglesWhole) keepLevelTrianglesWhole(mesh, mr, parent, per, cand, o.param.threads);
        if (cand.count <= parent.chartCount) {
            res.rejected.push_back({cand.level, cand.count, "keeping level triangles whole leaves nothing to split"});
            continue;
        }
        // A rank only refines T0: when its (more numerous) charts cannot fit the texture, the
        // hierarchy stops at the ranks it has, and the report says why. A split already past what
        // the page holds at any density stops it before its solves: those could only keep whole
        // the parents whose pieces come out worse in every round, and a rank of that many charts
        // that fits only so would be all gutters.
        const size_t capacity = shelfPackCapacity(o.param.textureSize, o.param.gutter);
        if (cand.count > capacity) {
            res.rejected.push_back({cand.level, cand.count,
                                    "its charts do not fit the texture (" + std::to_string(cand.count) + " charts; a " +
                                        std::to_string(o.param.textureSize) + " atlas holds at most " + std::to_string(capacity) +
                                        " at any density)"});
            break;
        }
        // Re-split rounds re-solve the unchanged charts of the candidate: its solves are remembered
        // (another candidate serves other levels, so its charts have other pairs: none would hit).
        o.param.solveCache = makeChartSolveCache();
        try {
            solveRankLayout(mesh, mr, parent, res.ranks.size() == 1, o, eo, base, per, cand, rr);
        } catch (const Impossible& e) {
            res.rejected.push_back({cand.level, cand.count, std::string("its charts do not fit the texture (") + e.what() + ")"});
            break;
        } catch (const SolverError& e) {
            // A rank is a refinement: when its layout does not validate (folded or overlapping UV
            // triangles the solver could not remove), T0 or the coarser ranks serve its levels.
            o.param.solveCache.reset();
            res.rejected.push_back({cand.level, cand.count, std::string("its layout does not validate (") + e.what() + ")"});
            res.warnings.push_back("rank " + std::to_string(j) + " from level " + std::to_string(cand.level) +
                                   " dropped: " + e.what() + "; the coarser ranks serve its levels");
            continue;
        }
        o.param.solveCache.reset();
        if (rr.layout.chartCount <= parent.chartCount) {
            res.rejected.push_back({cand.level, rr.layout.chartCount, "no piece solved better than its parent"});
            continue;
        }
        step();
        const bool better = trimServedLevels(mesh, mr, o, eo, base, rr);
        step();
        if (!better) {
            res.rejected.push_back({cand.level, rr.layout.chartCount, "does not lower both E and the area-ratio std-dev of T0"});
            continue;
        }
        res.ranks.push_back(std::move(rr));
        ++j;
    }
    bakeHierarchy(asset, o, res, step);
    res.seconds = secondsSince(t0);
    return res;
}

void applyTextureHierarchy(Asset& asset, Multires& mr, const RefineResult& result) {
    TextureHierarchy h;
    for (const RankResult& rr : result.ranks)
        if (rr.rank > 0) h.ranks.push_back(rr.layout);
    for (const RefinedImage& img : result.images) {
        if (img.rank > h.ranks.size()) throw InvalidInput("applyTextureHierarchy: image of an unknown rank");
        HierarchyTexture t;
        t.rank = img.rank;
        t.firstLevel = 0;
        t.lastLevel = result.ranks.at(img.rank).lastLevel;
        t.size = img.size;
        if (!img.image.encoded.empty()) {  // not baked (bakeImages false): the entry has no image
            asset.images.push_back(img.image);
            t.image = int(asset.images.size()) - 1;
        }
        h.textures.push_back(t);
        if (img.rank > 0) {
            ChartLayout& lay = h.ranks[img.rank - 1];
            lay.material = -1;
            lay.image = t.image;  // the largest size (sizes ascend)
        }
    }
    mr.textures = std::move(h);
}

}  // namespace lodbake

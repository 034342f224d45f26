// A level's texture layout chosen by its bake (layout_choice.h).
#include "lod/layout_choice.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <string>
#include <vector>

#include "lodbake/core/parallel.h"

#include "lod/level_mesh.h"
#include "lod/page_bake.h"
#include "lod/rank_choice.h"

namespace lodbake::lod_detail {
namespace {

// Scored pages are packed at half the level's page side, and below this side when that is larger
// (texels): a 2048 page (LOD0 when the source texels do not fit) is scored at 512 a side.
constexpr double kScoredMaxSide = 512;
// Candidates scored side by side: at most this many, of a level of at most this many triangles.
constexpr size_t kSideBySideCandidates = 4;
constexpr size_t kSideBySideTriangles = 200000;

// The choice between pages that would all bake one colour: every candidate deviates 0, so the
// energy rule's pick stands (the candidates are listed unscored: no page).
LayoutChoice unscoredChoice(const PlannedLevel& planned) {
    LayoutChoice choice;
    PackLevelReport::RankChoice& rc = choice.report;
    choice.rank = rc.byEnergy = planned.rank;
    for (uint32_t rank : planned.eligibleRanks) rc.candidates.push_back({rank, 0, 0, 0, 0, 0, 0});
    rc.reason = (planned.rank == 0 ? std::string("T0") : "rank " + std::to_string(planned.rank)) +
                ", the energy rule's pick: no image to compare (a constant base colour, no normal map)";
    return choice;
}

}  // namespace

LayoutChoice chooseLayoutByBake(const BakeSources& sources, std::vector<LayoutData>& layouts, const ChoiceLevel& level,
                                std::optional<FaceGrid>& grid, const PackResult& res, const PackOptions& options) {
    const Asset& asset = sources.asset();
    const TriMesh& mesh = asset.mesh;
    const LevelView& view = *level.view;
    const PlannedLevel& planned = *level.plan;
    const size_t k = level.index;
    const bool normal = level.normalMap, projected = level.projected;
    if (!level.colorTexture && !normal) return unscoredChoice(planned);
    if (!grid) grid.emplace(projectionGrid(mesh, options.threads));
    BakeChannels channels;  // base colour, and the normal map
    channels.normal = normal;
    const double reach = projectionReach(level.hausdorff, res.diagonal);  // the level bake's
    // The probe: every level triangle in a cell of its own, baked by projection like a coarse level.
    const std::vector<Vec3>& positions = view.positionsOr(mesh);
    std::vector<std::array<Vec3, 3>> triangles(view.triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t)
        for (size_t j = 0; j < 3; ++j) triangles[t][j] = positions[view.triangles[t][j]];
    const ProbeLayout probe = probeLayout(triangles);
    LodLevelData cells;
    for (size_t i = 0; i < probe.triangles.size(); ++i)
        for (size_t j = 0; j < 3; ++j) {
            const Vec3& p = triangles[probe.triangles[i]][j];
            cells.positions.insert(cells.positions.end(), {float(p.x), float(p.y), float(p.z)});
            cells.uvs.insert(cells.uvs.end(), {float(probe.uv[i][j].x), float(probe.uv[i][j].y)});
            cells.indices.push_back(uint32_t(cells.indices.size()));
        }
    const BakeTarget probeFrames = objectSpaceTarget(probe.uv);
    BakeResult probeBake;
    auto bakeProbe = [&] {
        probeBake = bakeProjected(sources, *grid, cells, probe.triangles.size(), probe.side, probe.side, reach, res.diagonal, channels,
                                  normal ? &probeFrames : nullptr, options.threads);
    };
    const PageChannels probePage{probe.side, probe.side, &probeBake.pixels, &probeBake.normal};  // once baked

    // Half the side, or less for a page that needs more than 2 x kScoredMaxSide a side (LOD0 when
    // the source texels do not fit): scale s of the texel limit, page cap and mip sides, log2(1/s)
    // mips fewer (the same share of gutters).
    const double scale = std::min(0.5, kScoredMaxSide / std::max(1.0, planned.sideNeeded));
    const int fewerMips = int(std::lround(std::log2(1 / scale)));
    PackOptions half = options;
    half.maxSize = std::max(16, int(options.maxSize * scale));
    half.minMipSide = std::max(1, int(options.minMipSide * scale));
    half.maxMips = std::max(0, options.maxMips - fewerMips);
    PageRequest request;
    request.texelLimit = scale * planned.texelLimit;
    request.coverage = planned.coverage;
    request.maxCoverage = planned.maxCoverage;
    request.originalTriangles = k == 0;
    request.startNearCap = true;  // scored, not kept
    // The finer level's page at the same scale: a level's page holds no more texels than the
    // finer one's, a cap that decides many coarse pages' density.
    if (k > 0) {
        const std::array<int, 2>& f = level.finerPage;
        request.finerPage = std::array<int, 2>{int(std::ceil(f[0] * scale)), int(std::ceil(f[1] * scale))};
    }
    // Each candidate's score: its layout's UVs, page, mesh and bake (score), then the bake's
    // deviation from the probe's (deviate).
    const std::vector<uint32_t>& ranks = planned.eligibleRanks;
    std::vector<RankCandidate> candidates(ranks.size());
    struct Baked {
        BakeResult bake;
        std::vector<std::array<Vec2, 3>> pageUV;
    };
    auto score = [&](size_t i, Baked& out) {
        const uint32_t rank = ranks[i];
        LayoutData& lay = layouts[rank];
        const LevelUVs luv = projected ? ownCharts(mesh, lay, view, levelUVs(mesh, lay, view, view.data, options.threads))
                                       : levelUVs(mesh, lay, view, view.data, options.threads);
        const LevelAtlas la = packLevelPage(lay, luv, request, half);
        const int w = la.atlas.width, h = la.atlas.height, size = std::max(w, h);
        LodLevelData L;
        buildLevelMesh(asset, view, luv, la, L);
        std::vector<std::array<Vec2, 3>> pageUV(view.triangles.size()), bakeUV(view.triangles.size());
        for (size_t t = 0; t < pageUV.size(); ++t)
            for (size_t j = 0; j < 3; ++j) {
                const uint32_t v = L.indices[3 * t + j];
                pageUV[t][j] = {L.uvs[2 * v], L.uvs[2 * v + 1]};
                bakeUV[t][j] = {pageUV[t][j].x * w / size, pageUV[t][j].y * h / size};
            }
        const BakeTarget frames = objectSpaceTarget(std::move(bakeUV));
        const BakeTarget* framesOrNull = normal ? &frames : nullptr;
        BakeResult baked = projected ? bakeProjected(sources, *grid, L, view.triangles.size(), w, h, reach, res.diagonal,
                                                           channels, framesOrNull, options.threads)
                                           : bakePage(sources, lay, la, channels, framesOrNull, options.threads, false);
        RankCandidate& c = candidates[i];
        c.rank = rank;
        c.width = w;
        c.height = h;
        c.charts = la.charts;
        out.bake = std::move(baked);
        out.pageUV = std::move(pageUV);
    };
    auto deviate = [&](size_t i, Baked& b) {
        RankCandidate& c = candidates[i];
        c.deviation = textureDeviation(probe, probePage, PageChannels{c.width, c.height, &b.bake.pixels, &b.bake.normal}, b.pageUV);
        b = {};
    };
    // The probe and the candidates are independent (each candidate reads and fills only its own
    // layout; the source images decode once, whichever bake asks first; the grid is read only), so
    // with a few candidates of a small level they are baked side by side, each bake still on every
    // thread: one's serial steps (UVs, page search, mesh) overlap the others' work. A large level's
    // are baked one after another (their UV lists and meshes would add up at the peak), each
    // candidate's bake dropped once it is scored. Errors as one after another: the probe's, then
    // the first candidate's.
    std::vector<uint32_t> distinct = ranks;
    std::sort(distinct.begin(), distinct.end());
    const bool sideBySide = ranks.size() > 1 && ranks.size() <= kSideBySideCandidates && resolveThreads(options.threads) > 1 &&
                            view.triangles.size() <= kSideBySideTriangles &&
                            std::adjacent_find(distinct.begin(), distinct.end()) == distinct.end();
    if (sideBySide) {
        std::vector<Baked> baked(ranks.size());
        std::vector<std::exception_ptr> errors(ranks.size() + 1);  // the probe's, then the candidates'
        parallelFor(ranks.size() + 1, int(ranks.size() + 1), [&](size_t t) {
            try {
                if (t == 0) bakeProbe();
                else score(t - 1, baked[t - 1]);
            } catch (...) {
                errors[t] = std::current_exception();
            }
        });
        for (const std::exception_ptr& e : errors)
            if (e) std::rethrow_exception(e);
        for (size_t i = 0; i < ranks.size(); ++i) deviate(i, baked[i]);
    } else {
        bakeProbe();
        for (size_t i = 0; i < ranks.size(); ++i) {
            Baked b;
            score(i, b);
            deviate(i, b);
        }
    }
    LayoutChoice choice;
    PackLevelReport::RankChoice& rc = choice.report;
    rc.byEnergy = planned.rank;
    const size_t best = chooseCandidate(candidates, rc.byEnergy);
    choice.rank = candidates[best].rank;
    for (const RankCandidate& c : candidates)
        rc.candidates.push_back({c.rank, c.deviation.score, c.deviation.color, c.deviation.normal, c.width, c.height, c.charts});
    rc.reason = choiceReason(candidates, best, rc.byEnergy);
    return choice;
}

}  // namespace lodbake::lod_detail

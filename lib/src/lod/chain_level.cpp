// buildLevel (chain_level.h): one level of the chain, as a script of three steps:
//   1. its layout: LOD0 on the original's texels (source_texels.h) when they fit, else the rank
//      the plan names or, with several eligible, the one its bake chooses (layout_choice.h);
//   2. its page and mesh: the layout's UVs (own charts for a projected level), the page search
//      (level_page.h), one indexed primitive (level_mesh.h); a tiled level keeps the original's
//      UVs on one period of its material (tiled_levels.h);
//   3. its bake and material: back faces, tangents and the normal maps' target frames, the page
//      bake (page_bake.h) or the previous level's material when it would bake the same, the
//      material (level_material.h) and the variants' (level_variants.h).
#include "lod/chain_level.h"

#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "lodbake/core/timing.h"
#include "lodbake/texture/codec.h"
#include "lod/layout_choice.h"
#include "lod/level_mesh.h"
#include "lod/page_bake.h"
#include "lod/source_texels.h"

namespace lodbake::lod_detail {
namespace {

// Wall and process CPU seconds of consecutive steps.
struct StepClock {
    Clock::time_point wallStart = Clock::now();
    double cpuStart = processCpuSeconds();
    void lap(double& wall, double& cpu) {
        const double c = processCpuSeconds();
        wall = secondsSince(wallStart);
        cpu = c - cpuStart;
        wallStart = Clock::now();
        cpuStart = c;
    }
};

// A normal map is baked when asked for always, or, on auto, when the material shows one or the
// level is coarser than the original (`coarser`: the map carries the detail the simplified
// surface lost; a level that kept the original's surface lost none).
bool normalMapWanted(const PackOptions& o, bool normalTexture, bool coarser = false) {
    return !o.baseColorOnly &&
           (o.normalMaps == NormalMaps::Always || (o.normalMaps == NormalMaps::Auto && (normalTexture || coarser)));
}

// Whether a bake with `channels` (and the plan's base colour) makes any image: none makes a
// material of factors only.
bool bakesAnImage(const MaterialPlan& plan, const BakeChannels& c) {
    return plan.baseColorTexture || c.alpha || c.orm || c.emissive || c.normal || c.clearcoat || c.clearcoatNormal || c.sheen ||
           c.specular || c.transmission || c.iridescence || c.diffuseTransmission || c.anisotropy;
}

// The plan's figures for the level, into its report.
void recordPlan(const PlannedLevel& l, PackLevelReport& r) {
    r.coverage = l.coverage;
    r.maxCoverage = l.maxCoverage;
    r.switchDistance = l.switchDistance;
    r.texelLimit = l.texelLimit;
    r.sideNeeded = l.sideNeeded;
    r.rank = r.rankChoice.byEnergy = l.rank;
    r.textureSize = l.textureSize;
}

// A tiled level's page (tiled_levels.h): one chart, the tile, its UVs kept as they are.
LevelAtlas tiledPage(const TilingEligibility& tiling, PackLevelReport& r) {
    LevelAtlas la;
    la.atlas.width = r.width = tiling.width;
    la.atlas.height = r.height = tiling.height;
    la.atlas.charts = {ChartPlacement{{double(tiling.width), 0, 0, 0, double(tiling.height), 0}}};
    la.chartSlot = {0};
    la.charts = r.charts = 1;
    return la;
}

// Level k while it is built.
struct LevelWork {
    size_t k = 0;
    bool original = false;   // Lod0::Original: LOD0 is the input asset, nothing of it is baked
    bool projected = false;  // baked by projection from the original surface (the coarse levels)
    bool coarser = false;    // its surface is not the original's as the original shades it (level_view.h)
    PackLevelReport& report;
    PackLevelProfile& time;
};

// 1. Several layouts eligible: the one whose bake shows the least texture deviation (the original
// as LOD0 bakes none).
void chooseRank(const ChainInputs& in, const LevelWork& w, ChainCarry& carry, const PackResult& res) {
    const PlannedLevel& pl = in.plan.levels[w.k];
    if (!in.options.rankByBake || pl.eligibleRanks.size() <= 1 || (w.original && w.k == 0)) return;
    const auto tChoice = Clock::now();
    const double cpuChoice = processCpuSeconds();
    const bool normalMap = normalMapWanted(in.options, in.materials.normalTexture, w.coarser);
    ChoiceLevel level{&in.views[w.k], w.k, &pl, w.report.hausdorff, w.projected, normalMap, in.materials.baseColorTexture};
    if (w.k > 0) level.finerPage = carry.capPage.value_or(std::array<int, 2>{res.reports[w.k - 1].width, res.reports[w.k - 1].height});
    LayoutChoice choice = chooseLayoutByBake(in.sources, in.layouts, level, carry.grid, res, in.options);
    w.time.rankChoiceSeconds = secondsSince(tChoice);
    w.time.rankChoiceCpuSeconds = processCpuSeconds() - cpuChoice;
    w.report.rank = choice.rank;
    w.report.textureSize = hierarchyTextureSize(in.textures, w.report.rank, pl.texelLimit / in.layouts[w.report.rank].uvPerUnit);
    w.report.rankChoice = std::move(choice.report);
}

// 1. LOD0 on the original's texels: their layout (`layout`, which `data` points into) and what
// packing needs of it; `data` stays empty when the asset has none. `capData`: the same for the
// layout whose page caps LOD1's texels, when it differs (SourceTexelLayout::capLayout).
void sourceTexels(const ChainInputs& in, const LevelWork& w, std::optional<SourceTexelLayout>& layout,
                  std::optional<LayoutData>& data, std::optional<LayoutData>& capData) {
    std::vector<std::pair<int, int>> sizes;
    for (const Image& image : in.asset.images) sizes.push_back(imageSize(image));
    const PlannedLevel& pl = in.plan.levels[w.k];
    layout = sourceTexelLayout(in.asset, sizes, *in.layouts[0].ch, pl.texelLimit / in.layouts[0].uvPerUnit);
    if (!layout->layout.empty()) {
        data.emplace(layoutData(in.asset, layout->layout, w.report.rank));
        data->inPlaceCharts = uint32_t(layout->inPlace);
        if (!layout->capLayout.empty()) {
            capData.emplace(layoutData(in.asset, layout->capLayout, w.report.rank));
            capData->inPlaceCharts = uint32_t(layout->inPlace);
        }
    }
    w.report.sourceTexelsNote = layout->reason;
}

// The level's page, and the layout it packs.
struct LevelPage {
    LevelAtlas la;
    LayoutData* layout = nullptr;
    bool sourceTexels = false;  // the page copies the original's texels (LOD0)
    LayoutData* capLayout = nullptr;  // with source texels: the layout whose page caps LOD1's (none: the page's own)
};

// 2. The level's page over `layout` (the source texels' at LOD0, when they fit the page whole),
// and its mesh in L unless the level is the original as LOD0 (false: the page only, for LOD1's
// texel cap).
bool placeLevel(const ChainInputs& in, const LevelWork& w, ChainCarry& carry, PackResult& res, std::optional<TiledLevelUVs>& tiled,
                LevelPage& page, StepClock& clock, LodLevelData& L) {
    const TriMesh& mesh = in.asset.mesh;
    const LevelView& view = in.views[w.k];
    const PlannedLevel& pl = in.plan.levels[w.k];
    PackLevelReport& r = w.report;
    PageRequest request;
    request.texelLimit = pl.texelLimit;
    request.coverage = pl.coverage;
    request.maxCoverage = pl.maxCoverage;
    request.originalTriangles = w.k == 0;
    request.sourceTexels = page.sourceTexels;
    request.widenGutters = true;
    if (w.k > 0) {
        request.finerPage = carry.capPage.value_or(std::array<int, 2>{res.reports[w.k - 1].width, res.reports[w.k - 1].height});
        request.finerDensity = res.reports[w.k - 1].texelsPerUnit;
    }
    if (!request.sourceTexels) page.layout = &in.layouts[r.rank];
    if (tiled) {  // the original's texture coordinates on the tile
        page.la = tiledPage(in.tiling, r);
        carry.capPage.reset();
        if (w.original && w.k == 0) return false;
        LevelUVs luv;
        luv.uv = std::move(tiled->uv);
        luv.chart.assign(luv.uv.size(), 0);
        buildLevelMesh(in.asset, view, luv, page.la, L);
        return true;
    }
    // The level's layout UVs end with its mesh, before the bake.
    const int threads = in.options.threads;
    LevelUVs luv = w.projected ? ownCharts(mesh, *page.layout, view, levelUVs(mesh, *page.layout, view, view.data, threads))
                               : levelUVs(mesh, *page.layout, view, view.data, threads);
    clock.lap(w.time.wall.uvs, w.time.cpu.uvs);
    page.la = packLevelPage(*page.layout, luv, request, in.options, &carry.pages);
    if (request.sourceTexels && page.la.atlas.texelsPerUnit < 1) {
        r.sourceTexelsNote = "the original's texture islands do not fit a " + std::to_string(in.options.maxSize) + " page";
        request.sourceTexels = false;
        chooseRank(in, w, carry, res);
        page.layout = &in.layouts[r.rank];
        luv = levelUVs(mesh, *page.layout, view, view.data, threads);
        page.la = packLevelPage(*page.layout, luv, request, in.options, &carry.pages);
    }
    page.sourceTexels = r.sourceTexels = request.sourceTexels;
    clock.lap(w.time.wall.page, w.time.cpu.page);
    recordPage(page.la, *page.layout, r);
    carry.capPage = page.la.capPage;
    if (page.sourceTexels && page.capLayout)
        carry.capPage = packLevelPage(*page.capLayout, levelUVs(mesh, *page.capLayout, view, view.data, threads), request, in.options, &carry.pages)
                             .capPage;
    carry.pages.forgetLarge();
    r.absorbedIslands = luv.absorbedIslands;
    if (w.original && w.k == 0) return false;
    buildLevelMesh(in.asset, view, luv, page.la, L);
    return true;
}

// 3. The level's bake and material, its back faces and their draw groups.
void bakeLevel(const ChainInputs& in, const LevelWork& w, ChainCarry& carry, PackResult& res, bool tiled, LevelPage& page,
               std::vector<uint32_t>& groups, StepClock& clock, LodLevelData& L) {
    const size_t k = w.k;
    const PackOptions& options = in.options;
    const LevelAtlas& la = page.la;
    PackLevelReport& r = w.report;
    const size_t front = L.indices.size() / 3;
    const std::vector<size_t> backSource = in.materials.backFaces ? addBackFaces(in.asset, in.views[k], L) : std::vector<size_t>{};
    if (in.split.groups.size() > 1) {
        for (size_t t = 0; t < front; ++t) groups.push_back(in.split.groupOf[in.views[k].faces[t]]);
        for (size_t t : backSource) groups.push_back(groups[t]);
    }
    // The level's channels for a material plan: the default's, or a variant's.
    auto channelsOf = [&](const MaterialPlan& p) { return levelChannels(p, normalMapWanted(options, p.normalTexture, w.coarser)); };
    const BakeChannels channels =
        tiled ? levelChannels(in.materials, normalMapWanted(options, in.materials.normalTexture)) : channelsOf(in.materials);
    const bool normalMaps =
        channels.normal || channels.clearcoatNormal || channels.anisotropy || variantsNeedTangents(in.variants, channelsOf);
    if (normalMaps) L.tangents = levelTangents(L);
    // The normal maps' target frames; none without one.
    std::optional<BakeTarget> target;
    if (normalMaps && !tiled) target = levelBakeTarget(L, la.atlas.width, la.atlas.height);
    const BakeTarget* targetOrNull = target ? &*target : nullptr;
    clock.lap(w.time.wall.mesh, w.time.cpu.mesh);
    const double reach = projectionReach(r.hausdorff, res.diagonal);
    // A projected level with the previous projected level's mesh, page and reach (and so its
    // channels: every coarser level has the same) bakes the same: its material is copied.
    const LodLevelData* previous = k > 1 ? &res.levels[k - 1 - (w.original ? 1 : 0)] : nullptr;
    const bool repeat = w.projected && previous && reach == carry.previousReach && la.atlas.width == res.reports[k - 1].width &&
                        la.atlas.height == res.reports[k - 1].height && sameLevelMesh(L, *previous);
    const bool bakes = !repeat && !tiled && bakesAnImage(in.materials, channels);  // else factors only
    if (w.projected && !carry.grid && (bakes || (!repeat && !tiled && !in.variants.empty()))) carry.grid.emplace(projectionGrid(in.asset.mesh, in.options.threads));
    auto bake = [&](const BakeSources& s, const BakeChannels& c) {
        return w.projected ? bakeProjected(s, *carry.grid, L, front, la.atlas.width, la.atlas.height, reach, res.diagonal, c,
                                           targetOrNull, options.threads)
                           : bakePage(s, *page.layout, la, c, targetOrNull, options.threads, page.sourceTexels);
    };
    BakeResult baked;
    if (tiled && !carry.tile) {
        baked = bakeTile(in.asset, in.tiling, channels, options.threads);
        carry.tile = levelMaterial(in.materials, baked, in.tiling.width, in.tiling.height, in.images, "tile");
        carry.tile->repeat = true;
        std::tie(carry.tile->minFilter, carry.tile->magFilter) = sourceFilters(in.asset);  // its texels are the source's
    } else if (bakes)
        baked = bake(in.sources, channels);
    carry.previousReach = w.projected && !tiled ? reach : -1;
    w.time.bakeSeconds = baked.seconds;
    clock.lap(w.time.wall.bake, w.time.cpu.bake);
    L.material = tiled    ? *carry.tile
                 : repeat ? previous->material
                          : levelMaterial(in.materials, baked, la.atlas.width, la.atlas.height, in.images, L.name);
    if (page.sourceTexels) std::tie(L.material.minFilter, L.material.magFilter) = sourceFilters(in.asset);
    if (repeat && !in.variants.empty()) copyLevelVariants(*previous, in.variants, L, r);
    if (!repeat && !in.variants.empty())  // the same bake with each variant's sources and channels
        bakeLevelVariants(
            in.variants, channelsOf, bake,
            [&](const MaterialPlan& p, const BakeResult& b, const std::string& name) {
                return levelMaterial(p, b, la.atlas.width, la.atlas.height, in.images, name);
            },
            L, r);
    clock.lap(w.time.wall.material, w.time.cpu.material);
    r.channels = channelNames(L.material);
    r.triangles = L.indices.size() / 3;
    r.vertices = L.positions.size() / 3;
}

}  // namespace

void buildLevel(const ChainInputs& in, size_t k, ChainCarry& carry, PackResult& res, std::vector<uint32_t>& groups,
                PackLevelProfile& time) {
    const TriMesh& mesh = in.asset.mesh;
    const LevelView& view = in.views[k];
    const bool original = in.options.lod0 == Lod0::Original;
    const bool coarser = k > 0 && !showsOriginalSurface(mesh, view);
    const LevelWork w{k, original, k > 0 && in.options.projectLevels, coarser, res.reports[k], time};
    recordPlan(in.plan.levels[k], w.report);
    w.report.tiling.note = in.tiling.reason;
    std::optional<TiledLevelUVs> tiled;
    if (in.tiling.eligible) tiled = tiledLevel(mesh, view.positionsOr(mesh), view.triangles, view.faces, in.tiling, w.report.tiling);

    // 1. LOD0 on the source texels needs no rank choice, unless they do not fit (placeLevel).
    std::optional<SourceTexelLayout> sourceLayout;
    std::optional<LayoutData> sourceData, sourceCapData;
    if (k == 0 && in.options.sourceTexels && !tiled) sourceTexels(in, w, sourceLayout, sourceData, sourceCapData);
    if (!(k == 0 && sourceData) && !tiled) chooseRank(in, w, carry, res);

    StepClock clock;
    LodLevelData scratch;  // LOD0's mesh when the original is LOD0: never built
    LodLevelData& L = original ? (k > 0 ? res.levels[k - 1] : scratch) : res.levels[k];
    L.name = "LOD" + std::to_string(k);
    LevelPage page;
    page.sourceTexels = k == 0 && sourceData;
    if (page.sourceTexels) page.layout = &*sourceData;
    if (page.sourceTexels && sourceCapData) page.capLayout = &*sourceCapData;
    if (!placeLevel(in, w, carry, res, tiled, page, clock, L)) return;  // 2
    bakeLevel(in, w, carry, res, tiled.has_value(), page, groups, clock, L);  // 3
}

}  // namespace lodbake::lod_detail

// pack: parameterized multiresolution asset -> glTF LOD chain.
//
// packLodChain is the script; each step lives in its own file of lib/src/lod/:
//   1. layoutsOf (level_page.h): T0 (multires.charts) and, with a texture hierarchy, every rank
//      layout;
//   2. measureLevels (level_measure.h): two-sided Hausdorff / RMS distance of each level to the
//      original, after vertex placement (vertex_placement.h) where it applies;
//   3. planLevels (level_plan.h): each level's screen coverage range, the texel density it can
//      show, the layouts eligible for it and the page side it needs;
//   4. per level: with several layouts eligible, chooseLayoutByBake (layout_choice.h: the one
//      whose bake shows the least texture deviation); levelUVs and, for a level baked by
//      projection, ownCharts, then packLevelPage (level_page.h: the charts its triangles use
//      repacked at its density, gutters for the mips it uses); buildLevelMesh (level_mesh.h: one
//      indexed primitive); bakePage or bakeProjected (page_bake.h); levelMaterial
//      (level_material.h), and the variants' materials (level_variants.h);
//   5. with Lod0::Original, LOD0 is the input asset itself (readSourceScene): its page is packed
//      (LOD1's is held to its texels) but nothing is baked, and its report describes the original;
//   6. levels whose triangles span several draw groups split into one primitive each (level_parts.h).
// A repeating material keeps its tiling instead (tiled_levels.h): its levels take the original's
// texture coordinates on one baked period of the material, with no page search and one bake.
// Writing the chain is the pack stage's (stages/pack_write.h).
#include "lodbake/lod/lod_chain.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <tuple>

#include "lodbake/bake/bake.h"
#include "lodbake/bake/draw_split.h"
#include "lodbake/bake/material_plan.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/core/math.h"
#include "lodbake/core/timing.h"
#include "lodbake/texture/codec.h"
#include "lod/layout_choice.h"
#include "lod/level_material.h"
#include "lod/level_measure.h"
#include "lod/level_mesh.h"
#include "lod/level_page.h"
#include "lod/level_parts.h"
#include "lod/level_plan.h"
#include "lod/level_variants.h"
#include "lod/level_view.h"
#include "lod/page_bake.h"
#include "lod/source_texels.h"
#include "lod/tiled_levels.h"

namespace lodbake {
namespace {

using namespace lod_detail;

void checkInput(const Asset& asset, const Multires& mr) {
    const TriMesh& m = asset.mesh;
    const ChartLayout& ch = mr.charts;
    if (m.triangleCount() == 0) throw Impossible(asset.sourcePath + ": no triangles");
    if (ch.empty()) throw Impossible(asset.sourcePath + ": no chart layout (LODBAKE_multires charts); run parameterize first");
    if (ch.faceChart.size() != m.triangleCount() || ch.cornerUV.size() != m.triangleCount())
        throw InvalidInput(asset.sourcePath + ": chart layout does not match the original mesh");
    for (const Level& L : mr.levels) {
        if (L.faces.size() != L.triangles.size() || L.cornerWedges.size() != L.triangles.size())
            throw InvalidInput(asset.sourcePath + ": inconsistent multires level");
        for (uint32_t f : L.faces)
            if (f >= m.triangleCount()) throw InvalidInput(asset.sourcePath + ": level face out of range");
        for (const Tri& t : L.triangles)
            for (uint32_t x : t)
                if (x >= m.vertexCount()) throw InvalidInput(asset.sourcePath + ": level vertex out of range");
        for (const Tri& t : L.cornerWedges)
            for (uint32_t x : t)
                if (x >= m.wedges.size()) throw InvalidInput(asset.sourcePath + ": level wedge out of range");
    }
}

// 5. The original as LOD0: it must be the chain's input (same flattened triangles).
SourceScene readOriginal(const Asset& asset, const PackOptions& options) {
    if (options.original.empty()) throw InvalidInput(asset.sourcePath + ": LOD0 'original' needs the original asset's path");
    SourceScene s = readSourceScene(options.original);
    if (s.triangles != asset.mesh.triangleCount())
        throw InvalidInput(options.original + ": not the original of " + asset.sourcePath + " (" + std::to_string(s.triangles) +
                           " triangles; the chain's original has " + std::to_string(asset.mesh.triangleCount()) + ")");
    return s;
}

// The report of LOD0 when it is the original: no page, bake or channels; deviation 0.
void describeOriginal(const SourceScene& s, PackLevelReport& r) {
    PackLevelReport o;
    o.source = "original asset";
    o.triangles = s.triangles;
    o.vertices = s.vertices;
    o.drawCalls = s.drawCalls;
    o.materials = s.materials;
    o.coverage = r.coverage;
    o.maxCoverage = r.maxCoverage;
    o.switchDistance = r.switchDistance;
    o.texelLimit = r.texelLimit;
    o.sideNeeded = r.sideNeeded;
    r = o;
}

LevelPlanOptions planOptions(const PackOptions& o) {
    LevelPlanOptions p;
    p.pixelError = o.pixelError;
    p.viewportHeight = o.viewportHeight;
    p.fovY = o.fovY;
    p.lod0Coverage = o.lod0Coverage;
    p.cutoffPixels = o.cutoffPixels;
    p.maxSize = o.maxSize;
    p.lod0Density = o.lod0Density;
    return p;
}

// What the plan reads of the measured chain: each level's deviation and multires level, the
// original's extent and area, the layouts' scales and (with `hierarchy`) the hierarchy's textures.
LevelPlanInput planInput(const Asset& asset, const Multires& mr, const std::vector<LevelView>& views,
                         const std::vector<LayoutData>& layouts, const PackResult& res, bool hierarchy) {
    const TriMesh& mesh = asset.mesh;
    LevelPlanInput in;
    for (size_t k = 0; k < views.size(); ++k) {
        in.hausdorff.push_back(res.reports[k].hausdorff);
        in.multiresLevel.push_back(views[k].level);
    }
    in.radius = res.radius;
    in.diagonal = res.diagonal;
    for (const Tri& t : mesh.triangles) in.area3D += triangleArea(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    for (const LayoutData& l : layouts) in.layoutUvPerUnit.push_back(l.uvPerUnit);
    if (hierarchy) in.textures = mr.textures.textures;
    return in;
}

// The plan's figures for level k, into its report.
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

// What glTF cannot vary per texel, kept exact by primitives on the same pages (draw_split.h):
// the triangles grouped for the default selection and each variant bake's.
struct ChainDraws {
    DrawSplit split;
    std::vector<size_t> selectionOfVariant;  // per variant: its selection (0 = the default's)
};

ChainDraws chainDraws(const Asset& asset, const MaterialPlan& plan, const ChainVariants& variants, const PackOptions& options,
                      std::vector<std::string>& warnings) {
    const TriMesh& mesh = asset.mesh;
    const std::vector<int32_t> noMaterials(mesh.triangleMaterial.empty() ? mesh.triangleCount() : 0, -1);
    std::vector<const std::vector<int32_t>*> selections{mesh.triangleMaterial.empty() ? &noMaterials : &mesh.triangleMaterial};
    for (const auto& b : variants.bakes) selections.push_back(&b->asset.mesh.triangleMaterial);
    DrawSplitOptions splitOptions;
    splitOptions.maxDraws = options.maxDraws;
    splitOptions.extensionProperties = plan.ext.any();  // else no material of the chain carries them
    for (const auto& b : variants.bakes) splitOptions.extensionProperties |= b->plan.ext.any();
    ChainDraws d;
    d.split = splitDraws(asset, selections, splitOptions);
    warnings.insert(warnings.end(), d.split.warnings[0].begin(), d.split.warnings[0].end());
    for (size_t v = 0; v < variants.names.size(); ++v) {
        const int b = variants.bakeOf[v];
        d.selectionOfVariant.push_back(b < 0 ? 0 : size_t(b) + 1);
        const bool first = b >= 0 && std::find(variants.bakeOf.begin(), variants.bakeOf.end(), b) - variants.bakeOf.begin() == std::ptrdiff_t(v);
        if (first)
            for (const std::string& w : d.split.warnings[size_t(b) + 1]) warnings.push_back("variant '" + variants.names[v] + "': " + w);
    }
    return d;
}

}  // namespace

PackResult packLodChain(const Asset& asset, const Multires& mr, const PackOptions& options) {
    auto t0 = Clock::now();
    PackProfile profile;  // where the time went, handed to options.profile
    checkInput(asset, mr);
    const TriMesh& mesh = asset.mesh;
    PackResult res;
    const bool original = options.lod0 == Lod0::Original;
    if (original) res.original = readOriginal(asset, options);
    res.diagonal = bounds(mesh).diagonal();
    res.radius = 0.5 * res.diagonal;
    if (!(res.radius > 0)) throw Impossible(asset.sourcePath + ": the mesh has no extent");
    std::vector<std::string> repeated;
    std::vector<LevelView> views = levelViews(asset, mr, repeated);
    const BakeSources sources(asset);  // the original images, decoded once for every level's bake
    const size_t n = views.size();
    auto progress = [&](double f) {
        if (options.progress && !options.progress(f)) throw Cancelled(asset.sourcePath + ": pack cancelled");
    };

    const bool hierarchy = options.useTextureHierarchy && !mr.textures.empty();
    std::vector<LayoutData> layouts = layoutsOf(asset, mr, hierarchy);  // 1
    const auto tMeasure = Clock::now();
    const double cpuMeasure = processCpuSeconds();
    measureLevels(asset, views, options, res, profile.levels, progress);  // 2
    profile.measureSeconds = secondsSince(tMeasure);
    profile.measureCpuSeconds = processCpuSeconds() - cpuMeasure;
    const LevelPlanInput planned = planInput(asset, mr, views, layouts, res, hierarchy);
    const LevelPlan plan = planLevels(planned, planOptions(options));  // 3
    res.screenCoverage = plan.screenCoverage;
    // The projection bakes' grid over the original, built for the first projected level: the
    // original triangles' page (the largest bake) runs without it.
    std::optional<FaceGrid> grid;
    double previousReach = -1;  // the previous level's projection reach (-1: not projected)

    // LOD0's layout on the original's texels (source_texels.h), made at LOD0.
    std::optional<SourceTexelLayout> sourceLayout;
    std::optional<LayoutData> sourceData;

    // 4. Per level: texture, page, mesh, bake.
    const MaterialPlan materials = options.baseColorOnly ? baseColorPlan(planMaterial(asset)) : planMaterial(asset);
    res.warnings = materials.warnings;
    const ChainVariants variants = chainVariants(asset, options.baseColorOnly);  // KHR_materials_variants (level_variants.h)
    res.warnings.insert(res.warnings.end(), variants.warnings.begin(), variants.warnings.end());
    res.variants = variants.names;
    const ChainDraws draws = chainDraws(asset, materials, variants, options, res.warnings);
    const DrawSplit& split = draws.split;
    std::vector<std::vector<uint32_t>> triangleGroups(n);  // per level, per triangle: its draw group
    res.warnings.insert(res.warnings.end(), repeated.begin(), repeated.end());
    res.rig = asset.rig;
    res.morph = asset.morph;
    res.scene = asset.scene;
    LevelImageOptions io;
    io.format = options.ktx2Encoder.empty() ? options.imageFormat : ImageFormat::Png;
    io.jpegQuality = options.jpegQuality;
    io.ktx2Encoder = options.ktx2Encoder;
    io.threads = options.threads;
    // A repeating material keeps its tiling: levels on one baked period of it (tiled_levels.h).
    const TilingEligibility tiling = options.keepTiling ? tilingEligibility(asset) : TilingEligibility{};
    const bool tileNormalMap = !options.baseColorOnly && (options.normalMaps == NormalMaps::Always ||
                                                          (options.normalMaps == NormalMaps::Auto && materials.normalTexture));
    std::optional<LodMaterial> tile;  // baked at the first tiled level
    res.levels.resize(original ? n - 1 : n);
    for (size_t k = 0; k < n; ++k) {
        PackLevelReport& r = res.reports[k];
        PackLevelProfile& time = profile.levels[k];
        const PlannedLevel& pl = plan.levels[k];
        recordPlan(pl, r);
        r.tiling.note = tiling.reason;
        std::optional<TiledLevelUVs> tiled;
        if (tiling.eligible)
            tiled = tiledLevel(mesh, views[k].positionsOr(mesh), views[k].triangles, views[k].faces, tiling, r.tiling);
        const bool projected = k > 0 && options.projectLevels;
        // Several layouts eligible: the one whose bake shows the least texture deviation (LOD0 on
        // the source texels needs none, unless they do not fit; the original as LOD0 bakes none).
        const bool levelNormalMap = !options.baseColorOnly && (options.normalMaps == NormalMaps::Always ||
                                                               (options.normalMaps == NormalMaps::Auto && (materials.normalTexture || k > 0)));
        auto chooseRank = [&] {
            if (!options.rankByBake || pl.eligibleRanks.size() <= 1 || (original && k == 0)) return;
            const auto tChoice = Clock::now();
            const double cpuChoice = processCpuSeconds();
            const ChoiceLevel level{&views[k], k, &pl, r.hausdorff, projected, levelNormalMap};
            LayoutChoice choice = chooseLayoutByBake(sources, layouts, level, grid, res, options);
            time.rankChoiceSeconds = secondsSince(tChoice);
            time.rankChoiceCpuSeconds = processCpuSeconds() - cpuChoice;
            r.rank = choice.rank;
            r.textureSize = hierarchyTextureSize(planned.textures, r.rank, pl.texelLimit / layouts[r.rank].uvPerUnit);
            r.rankChoice = std::move(choice.report);
        };
        if (k == 0 && options.sourceTexels && !tiled) {
            std::vector<std::pair<int, int>> sizes;
            for (const Image& image : asset.images) sizes.push_back(imageSize(image));
            sourceLayout = sourceTexelLayout(asset, sizes, *layouts[0].ch, pl.texelLimit / layouts[0].uvPerUnit);
            if (!sourceLayout->layout.empty()) {
                sourceData.emplace(layoutData(asset, sourceLayout->layout, r.rank));
                sourceData->inPlaceCharts = uint32_t(sourceLayout->inPlace);
            }
            r.sourceTexelsNote = sourceLayout->reason;
        }
        if (!(k == 0 && sourceData) && !tiled) chooseRank();
        auto tStep = Clock::now();
        double cpuStep = processCpuSeconds();
        auto lap = [&](double& wall, double& cpu) {
            const double c = processCpuSeconds();
            wall = secondsSince(tStep);
            cpu = c - cpuStep;
            tStep = Clock::now();
            cpuStep = c;
        };
        LodLevelData scratch;  // LOD0's mesh when the original is LOD0: never built
        LodLevelData& L = original ? (k > 0 ? res.levels[k - 1] : scratch) : res.levels[k];
        L.name = "LOD" + std::to_string(k);
        LevelAtlas la;
        // LOD0 on the source texels when they fit the page whole, else on the rank's layout.
        PageRequest request;
        request.texelLimit = pl.texelLimit;
        request.coverage = pl.coverage;
        request.maxCoverage = pl.maxCoverage;
        request.originalTriangles = k == 0;
        request.sourceTexels = k == 0 && sourceData;
        if (k > 0) request.finerPage = std::array<int, 2>{res.reports[k - 1].width, res.reports[k - 1].height};
        LayoutData* layout = request.sourceTexels ? &*sourceData : &layouts[r.rank];
        if (tiled) {  // the original's texture coordinates on the tile
            la = tiledPage(tiling, r);
            if (original && k == 0) continue;
            LevelUVs luv;
            luv.uv = std::move(tiled->uv);
            luv.chart.assign(luv.uv.size(), 0);
            buildLevelMesh(asset, views[k], luv, la, L);
        } else {  // the level's layout UVs end with its mesh, before the bake
            LevelUVs luv = projected ? ownCharts(mesh, *layout, views[k], levelUVs(mesh, *layout, views[k], views[k].data))
                                     : levelUVs(mesh, *layout, views[k], views[k].data);
            lap(time.wall.uvs, time.cpu.uvs);
            la = packLevelPage(*layout, luv, request, options);
            if (request.sourceTexels && la.atlas.texelsPerUnit < 1) {
                r.sourceTexelsNote = "the original's texture islands do not fit a " + std::to_string(options.maxSize) + " page";
                request.sourceTexels = false;
                chooseRank();
                layout = &layouts[r.rank];
                luv = levelUVs(mesh, *layout, views[k], views[k].data);
                la = packLevelPage(*layout, luv, request, options);
            }
            r.sourceTexels = request.sourceTexels;
            lap(time.wall.page, time.cpu.page);
            recordPage(la, *layout, r);
            r.absorbedIslands = luv.absorbedIslands;
            if (original && k == 0) continue;  // 5: the page only, for LOD1's texel cap
            buildLevelMesh(asset, views[k], luv, la, L);
        }
        const bool sourceTexels = request.sourceTexels;
        const size_t front = L.indices.size() / 3;
        const std::vector<size_t> backSource = materials.backFaces ? addBackFaces(asset, views[k], L) : std::vector<size_t>{};
        if (split.groups.size() > 1) {
            std::vector<uint32_t>& groups = triangleGroups[k];
            for (size_t t = 0; t < front; ++t) groups.push_back(split.groupOf[views[k].faces[t]]);
            for (size_t t : backSource) groups.push_back(groups[t]);
        }
        // The level's channels for a material plan: the default's, or a variant's.
        auto channelsOf = [&](const MaterialPlan& p) {
            return levelChannels(p, !options.baseColorOnly && (options.normalMaps == NormalMaps::Always ||
                                                               (options.normalMaps == NormalMaps::Auto && (p.normalTexture || k > 0))));
        };
        const BakeChannels channels = tiled ? levelChannels(materials, tileNormalMap) : channelsOf(materials);
        const bool normalMaps = channels.normal || channels.clearcoatNormal || channels.anisotropy || variantsNeedTangents(variants, channelsOf);
        if (normalMaps) L.tangents = levelTangents(L);
        // The normal maps' target frames; none without one.
        std::optional<BakeTarget> target;
        if (normalMaps && !tiled) target = levelBakeTarget(L, la.atlas.width, la.atlas.height);
        const BakeTarget* targetOrNull = target ? &*target : nullptr;
        lap(time.wall.mesh, time.cpu.mesh);
        const double reach = projectionReach(r.hausdorff, res.diagonal);
        // A projected level with the previous projected level's mesh, page and reach (and so its
        // channels: every coarser level has the same) bakes the same: its material is copied.
        const LodLevelData* previous = k > 1 ? &res.levels[k - 1 - (original ? 1 : 0)] : nullptr;
        const bool repeat = projected && previous && reach == previousReach && la.atlas.width == res.reports[k - 1].width &&
                            la.atlas.height == res.reports[k - 1].height && sameLevelMesh(L, *previous);
        if (projected && !grid && !repeat && !tiled) grid.emplace(mesh);
        BakeResult baked;
        if (tiled && !tile) {
            baked = bakeTile(asset, tiling, channels, options.threads);
            tile = levelMaterial(materials, baked, tiling.width, tiling.height, io, "tile");
            tile->repeat = true;
            std::tie(tile->minFilter, tile->magFilter) = sourceFilters(asset);  // its texels are the source's
        } else if (!repeat && !tiled)
            baked = projected ? bakeProjected(sources, *grid, L, front, la.atlas.width, la.atlas.height, reach, res.diagonal, channels,
                                              targetOrNull, options.threads)
                              : bakePage(sources, *layout, la, channels, targetOrNull, options.threads, sourceTexels);
        previousReach = projected && !tiled ? reach : -1;
        time.bakeSeconds = baked.seconds;
        lap(time.wall.bake, time.cpu.bake);
        L.material = tiled ? *tile : repeat ? previous->material : levelMaterial(materials, baked, la.atlas.width, la.atlas.height, io, L.name);
        if (sourceTexels) std::tie(L.material.minFilter, L.material.magFilter) = sourceFilters(asset);
        if (repeat && !variants.empty()) copyLevelVariants(*previous, variants, L, r);
        if (!repeat && !variants.empty())  // the same bake with each variant's sources and channels
            bakeLevelVariants(
                variants, channelsOf,
                [&](const BakeSources& s, const BakeChannels& c) {
                    return projected ? bakeProjected(s, *grid, L, front, la.atlas.width, la.atlas.height, reach, res.diagonal, c,
                                                     targetOrNull, options.threads)
                                     : bakePage(s, *layout, la, c, targetOrNull, options.threads, sourceTexels);
                },
                [&](const MaterialPlan& p, const BakeResult& b, const std::string& name) {
                    return levelMaterial(p, b, la.atlas.width, la.atlas.height, io, name);
                },
                L, r);
        lap(time.wall.material, time.cpu.material);
        r.channels = channelNames(L.material);
        r.triangles = L.indices.size() / 3;
        r.vertices = L.positions.size() / 3;
        progress(0.3 + 0.7 * double(k + 1) / double(n));
    }
    // 6. Levels whose triangles span several draw groups: ordered by group, one primitive each
    // (after every bake: a repeated level compares its mesh with the previous one as baked).
    for (size_t k = original ? 1 : 0; k < n && split.groups.size() > 1; ++k)
        splitLevel(split, triangleGroups[k], draws.selectionOfVariant, res.levels[original ? k - 1 : k], res.reports[k]);
    if (original) {  // LOD0's report describes the original, which none of the steps made
        describeOriginal(*res.original, res.reports[0]);
        profile.levels[0] = {};
    }
    profile.seconds = secondsSince(t0);
    if (options.profile) *options.profile = std::move(profile);
    return res;
}

}  // namespace lodbake

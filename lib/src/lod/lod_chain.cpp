// pack: parameterized multiresolution asset -> glTF LOD chain.
//
// packLodChain is the script; each step lives in its own file of lib/src/lod/:
//   1. layoutsOf (level_page.h): T0 (multires.charts) and, with a texture hierarchy, every rank
//      layout;
//   2. measureLevels (level_measure.h): two-sided Hausdorff / RMS distance of each level to the
//      original, after vertex placement (vertex_placement.h) where it applies;
//   3. planLevels (level_plan.h): each level's screen coverage range, the texel density it can
//      show, the layouts eligible for it and the page side it needs;
//   4. per level, finer first, buildLevel (chain_level.h): its layout (with several eligible,
//      chooseLayoutByBake in layout_choice.h: the one whose bake shows the least texture
//      deviation), level UVs and page (level_page.h: the charts its triangles use repacked at its
//      density, gutters for the mips it uses), mesh (level_mesh.h: one indexed primitive), bake
//      (page_bake.h) and material (level_material.h), and the variants' materials (level_variants.h);
//   5. with Lod0::Original, LOD0 is the input asset itself (readSourceScene): its page is packed
//      (LOD1's is held to its texels) but nothing is baked, and its report describes the original;
//   6. levels whose triangles span several draw groups split into one primitive each (level_parts.h).
// A repeating material keeps its tiling instead (tiled_levels.h): its levels take the original's
// texture coordinates on one baked period of the material, with no page search and one bake.
// Writing the chain is the pack stage's (stages/pack_write.h).
#include "lodbake/lod/lod_chain.h"

#include <algorithm>
#include <optional>

#include "lodbake/bake/bake.h"
#include "lodbake/bake/draw_split.h"
#include "lodbake/bake/material_plan.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/free_pages.h"
#include "lodbake/core/math.h"
#include "lodbake/core/timing.h"
#include "lod/chain_level.h"
#include "lod/level_material.h"
#include "lod/level_measure.h"
#include "lod/level_page.h"
#include "lod/level_parts.h"
#include "lod/level_plan.h"
#include "lod/level_variants.h"
#include "lod/level_view.h"
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

// How the levels' images are encoded: KTX2 through the encoder takes PNG in.
LevelImageOptions levelImageOptions(const PackOptions& options) {
    LevelImageOptions io;
    io.format = options.ktx2Encoder.empty() ? options.imageFormat : ImageFormat::Png;
    io.jpegQuality = options.jpegQuality;
    io.ktx2Encoder = options.ktx2Encoder;
    io.threads = options.threads;
    return io;
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
    if (original && options.original.empty())
        throw InvalidInput(asset.sourcePath + ": LOD0 'original' needs the original asset's path");
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
    returnFreedPages();  // the measure's trees and samples, freed on both threads' arenas
    const LevelPlanInput planned = planInput(asset, mr, views, layouts, res, hierarchy);
    const LevelPlan plan = planLevels(planned, planOptions(options));  // 3
    res.screenCoverage = plan.screenCoverage;
    // 4. Per level, finer first: layout, page, mesh, bake, material (chain_level.h).
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
    // A repeating material keeps its tiling: levels on one baked period of it (tiled_levels.h).
    const TilingEligibility tiling = options.keepTiling ? tilingEligibility(asset) : TilingEligibility{};
    const LevelImageOptions images = levelImageOptions(options);
    const ChainInputs chain{asset, views, sources, options, plan, planned.textures, materials, variants, split, tiling, images, layouts};
    ChainCarry carry;
    res.levels.resize(original ? n - 1 : n);
    for (size_t k = 0; k < n; ++k) {
        buildLevel(chain, k, carry, res, triangleGroups[k], profile.levels[k]);
        returnFreedPages();  // the level's bake buffers: the next level's peak starts clean
        progress(0.3 + 0.7 * double(k + 1) / double(n));
    }
    // 6. Levels whose triangles span several draw groups: ordered by group, one primitive each
    // (after every bake: a repeated level compares its mesh with the previous one as baked).
    for (size_t k = original ? 1 : 0; k < n && split.groups.size() > 1; ++k)
        splitLevel(split, triangleGroups[k], draws.selectionOfVariant, res.levels[original ? k - 1 : k], res.reports[k]);
    if (original) {  // LOD0's report describes the original, which none of the steps made
        // Read last: no step reads it, and its decoded file (some 100 MB on a million triangles)
        // would sit under the measure's and every level's peak.
        res.original = readOriginal(asset, options);
        describeOriginal(*res.original, res.reports[0]);
        profile.levels[0] = {};
    }
    profile.seconds = secondsSince(t0);
    if (options.profile) *options.profile = std::move(profile);
    return res;
}

}  // namespace lodbake

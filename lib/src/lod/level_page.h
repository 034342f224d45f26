// A level's page: the charts its triangles use, from its layout (T0 or a rank of the texture
// hierarchy), repacked at the texel density the level can show, with gutters for the mips it uses.
//
// Every level triangle takes the layout UVs of its corners (levelUVs); a level baked by
// projection then takes charts of its own (ownCharts: islands unfolded onto neighbouring charts).
// The page search (packLevelPage) sizes the gutters for the mips used between the level's largest
// and smallest coverage and holds a coarser level's page to the finer one's texel count.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "lodbake/atlas/atlas.h"
#include "lodbake/chart/chart_lookup.h"
#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"
#include "lodbake/lod/lod_chain.h"
#include "lod/level_view.h"

namespace lodbake::lod_detail {

// A chart layout (T0 or a rank layout of the texture hierarchy) with what packing needs of it.
struct LayoutData {
    const ChartLayout* ch = nullptr;
    uint32_t rank = 0;
    std::vector<std::vector<uint32_t>> chartFaces;
    std::vector<double> chartUvArea;  // charts, then islands (chart id chartCount + i)
    double uvPerUnit = 0;  // layout UV units per model unit (area-averaged)
    std::unique_ptr<ChartVertexUV> lookup;
    // Level-triangle islands (parameterize's fallback): sorted vertex triple -> island.
    std::map<std::array<uint32_t, 3>, uint32_t> island;
    // The original faces each island's bake samples (the charts of its corners): found on the
    // first page bake that places an island (islandFacesOf), as the original triangles' page
    // places none and the projected levels' pages take their own.
    std::vector<std::vector<uint32_t>> islandFaces;
    bool islandFacesFound = false;
    uint32_t inPlaceCharts = 0;  // charts [0, n) are the original's texture islands (AtlasChart::inPlace)
};

// \throw InvalidInput when `ch` does not match asset.mesh; Impossible when it has no area.
LayoutData layoutData(const Asset& asset, const ChartLayout& ch, uint32_t rank);

// T0 and, with `hierarchy`, every rank (faces, UV area, UV-to-model scale).
std::vector<LayoutData> layoutsOf(const Asset& asset, const Multires& mr, bool hierarchy);

// The original faces of each of the layout's islands (found once, on the first call).
const std::vector<std::vector<uint32_t>>& islandFacesOf(const TriMesh& mesh, LayoutData& d);

// The chart and layout UVs of every triangle of a level.
struct LevelUVs {
    std::vector<uint32_t> chart;
    std::vector<std::array<Vec2, 3>> uv;
    // Non-empty: the charts are the level's own (ownCharts), this is each one's level-triangle UV
    // area and ownChartSource the layout chart each grew from (>= the layout's chartCount: from an
    // island). Empty: the ids are the layout's charts and islands.
    std::vector<double> ownChartArea;
    std::vector<uint32_t> ownChartSource;
    size_t absorbedIslands = 0;  // own charts: islands unfolded onto a chart
};

// The layout UVs of every corner of level `lv` (`level`: its multires level, null for the original
// triangles). `threads` split the level's triangles and corner projections (never changes the
// UVs).
LevelUVs levelUVs(const TriMesh& mesh, const LayoutData& L, const LevelView& lv, const Level* level, int threads);

// A level baked by projection: islands unfolded onto neighbouring charts (level_islands.h).
LevelUVs ownCharts(const TriMesh& mesh, const LayoutData& L, const LevelView& lv, LevelUVs luv);

struct LevelAtlas {
    AtlasResult atlas;
    std::vector<int> chartSlot;  // original chart id -> index in atlas.charts, -1 if unused
    size_t charts = 0;
    // The page at the level's density before its gutters were widened: the coarser levels' cap.
    std::array<int, 2> capPage{};
};

// The level's charts packed with `ao`. `original`: the level is the original triangles, whose
// charts' faces are its own (no level triangles added to the footprints).
LevelAtlas packLevelAtlas(const LayoutData& L, const LevelUVs& luv, bool original, const AtlasOptions& ao);

// What a level's page is packed for (the plan's figures for the level, lod/level_plan.h).
struct PageRequest {
    double texelLimit = 0;                 // texels per model unit the level can show at its largest coverage
    double coverage = 0, maxCoverage = 0;  // the level's screen coverage range
    bool originalTriangles = false;        // the level is the original triangles (LOD0)
    // Source texels (LOD0): one page texel per layout unit (= per source texel), on whole texels.
    bool sourceTexels = false;
    // The next finer level's page (texels; none for LOD0): this page holds no more texels.
    std::optional<std::array<int, 2>> finerPage;
    // The next finer level's density (texels per model unit; none for LOD0): where this page is
    // denser, widening its gutters may lower it down to this.
    std::optional<double> finerDensity;
    // Widen the gutter towards the mips of the page's side where that keeps the density.
    bool widenGutters = false;
    // With a finer page far smaller than the limit's page: start at the density estimated to fit
    // the finer page rather than pack the limit's page only to shrink it. The page may differ from
    // the one shrunk from the limit (a few percent of density either way): for pages that are
    // compared, not kept (the rank choice's).
    bool startNearCap = false;
};

// The pages packed for the chain's levels, by what they were packed with. Packing is a function
// of its inputs, and packAtlas's of the gutter its search starts from (atlasStartGutter): a page
// asked for again with the same charts, or with a gutter that starts the same search, is the one
// packed before. Consecutive levels may pack the same charts (a coarser level whose mesh is the
// finer one's): the last kKeptChartSets distinct chart sets are kept.
class PackedPages {
public:
    AtlasResult pack(std::vector<AtlasChart> charts, const AtlasOptions& ao);
    // The set the last pack() packed, to be packed again by packKept without building and
    // comparing its charts anew (a million-triangle level's list is some 100 MB: two side by side
    // were a level's peak).
    uint64_t lastSet() const { return sets_.back().id; }
    // pack() of the charts of set `id` (a lastSet()), if it is still kept.
    std::optional<AtlasResult> packKept(uint64_t id, const AtlasOptions& ao);
    // Forgets the chart sets of more than kKeptCorners UV corners: a level's page step is done,
    // and a large set would stay in memory through the bakes (a million-triangle level's charts
    // are some 100 MB) for a repeat that only saves its packing.
    void forgetLarge();

private:
    static constexpr size_t kKeptChartSets = 2;
    static constexpr size_t kKeptCorners = 300000;
    struct Page {
        AtlasOptions ao;
        int start = 0;  // the gutter the search started from
        AtlasResult atlas;
    };
    struct ChartSet {
        uint64_t id = 0;
        std::vector<AtlasChart> charts;
        std::vector<Page> pages;
        std::array<std::vector<ChartFrame>, 2> frames;  // chartFrames, free and texel-aligned (found when first asked)
    };
    std::vector<ChartSet> sets_;  // the most recently used last
    uint64_t nextId_ = 0;

    AtlasResult packSet(ChartSet& c, const AtlasOptions& ao);
};

// The level's page: its charts packed at the density limit (layout units) with gutters for the
// mips used between its largest and smallest coverage (at most options.maxMips, none for pages
// below minMipSide). A page held below the density limit (maxSize) is magnified at the largest
// coverage and uses fewer mips: the gutter is narrowed to the fewest mips that the denser packing
// it allows still covers. A coarser level never carries more texels than the finer one (packing
// fewer, larger gutters can come out bigger at the same density): its density is lowered until it
// does not (at most 8 tries). With request.widenGutters the gutter then widens toward the mips of
// the page's side where that keeps the density, or lowers it no further than the finer level's
// (request.finerDensity) (la.capPage: the page before, the coarser levels' cap). Reads maxSize, powerOfTwo, maxMips, minMipSide and threads of `options`.
// `pages`, when given, holds the pages packed for other levels (else the level's own are kept).
LevelAtlas packLevelPage(const LayoutData& lay, const LevelUVs& luv, const PageRequest& request, const PackOptions& options,
                         PackedPages* pages = nullptr);

// The page figures of the report.
void recordPage(const LevelAtlas& la, const LayoutData& lay, PackLevelReport& r);

}  // namespace lodbake::lod_detail

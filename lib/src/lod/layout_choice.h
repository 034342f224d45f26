// A level's texture layout chosen by the bake: of the eligible layouts (T0 and ranks of the
// texture hierarchy), the one whose reduced bake shows the least texture deviation against a
// probe bake of the level's surface (the measure: lod/rank_choice.h).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "lodbake/bake/bake.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/lod/lod_chain.h"
#include "lod/level_page.h"
#include "lod/level_plan.h"
#include "lod/level_view.h"

namespace lodbake::lod_detail {

// The level a layout is chosen for.
struct ChoiceLevel {
    const LevelView* view = nullptr;
    size_t index = 0;            // k: LOD k of the chain
    const PlannedLevel* plan = nullptr;  // its plan (eligible ranks, texel limit, coverage range)
    double hausdorff = 0;        // its measured deviation (the projection bake's reach)
    bool projected = false;      // baked by projection (else the original triangles at the layout)
    bool normalMap = false;      // the level gets a normal map: it is compared too
    bool colorTexture = true;    // its base colour varies (a texture); else it is one factor, alike on every page
    std::array<int, 2> finerPage{};  // the finer level's cap page (texels; k > 0)
};

struct LayoutChoice {
    uint32_t rank = 0;
    PackLevelReport::RankChoice report;  // every candidate's score and why the rank won
};

// Each candidate's page packed at half the texel limit and page cap (a quarter of the texels; less
// above kScoredMaxSide), its level mesh built and its base colour (and normal map, in object
// space) baked the way the level's own bake runs, then read back at the probe's sample points of
// the level's surface. The reduced page costs a fraction of a full-size one; where it ranks
// candidates differently than full size would, their scores lie within chooseCandidate's margin.
// `res` holds the finer levels' reports (their pages cap this one's) and the diagonal. The probe
// and the projected bakes search the original through `grid` (built here when missing). The same
// for any thread count: each bake is, and the read-back runs in order. A level with neither a
// varying base colour nor a normal map has nothing to compare: every candidate deviates 0, none is
// packed or baked, and the energy rule's pick stands.
LayoutChoice chooseLayoutByBake(const BakeSources& sources, std::vector<LayoutData>& layouts, const ChoiceLevel& level,
                                std::optional<FaceGrid>& grid, const PackResult& res, const PackOptions& options);

}  // namespace lodbake::lod_detail

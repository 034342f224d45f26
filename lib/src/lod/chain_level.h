// One level of the chain built from its plan: its layout (LOD0 on the original's texels, or the
// rank its bake chooses), its level UVs and page, its mesh, its page bake and its material (and
// the variants'). packLodChain (lod_chain.cpp) prepares what every level reads once and calls
// buildLevel finer level first: a level's page holds no more texels than the finer one's, and a
// projected level that repeats the previous one's mesh, page and reach takes its material.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "lodbake/bake/bake.h"
#include "lodbake/bake/draw_split.h"
#include "lodbake/bake/material_plan.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/lod/lod_chain.h"
#include "lodbake/lod/pack_profile.h"
#include "lod/level_material.h"
#include "lod/level_page.h"
#include "lod/level_plan.h"
#include "lod/level_variants.h"
#include "lod/level_view.h"
#include "lod/tiled_levels.h"

namespace lodbake::lod_detail {

// What every level reads: the chain's input and what packLodChain prepared once for all levels.
struct ChainInputs {
    const Asset& asset;
    const std::vector<LevelView>& views;
    const BakeSources& sources;  // the original images, decoded once for every level's bake
    const PackOptions& options;
    const LevelPlan& plan;
    const std::vector<HierarchyTexture>& textures;  // the texture hierarchy's; empty: T0 only
    const MaterialPlan& materials;                  // the chain's one material (material_plan.h)
    const ChainVariants& variants;                  // KHR_materials_variants (level_variants.h)
    const DrawSplit& split;                         // the draw groups (draw_split.h)
    const TilingEligibility& tiling;                // a repeating material's tiling (tiled_levels.h)
    const LevelImageOptions& images;                // how the levels' images are encoded
    std::vector<LayoutData>& layouts;               // T0, then the ranks; a page bake finds their island faces once
};

// What a level hands on to the coarser ones.
struct ChainCarry {
    // The projection bakes' grid over the original, built for the first projected level that
    // bakes: the original triangles' page (the largest bake) runs without it.
    std::optional<FaceGrid> grid;
    double previousReach = -1;        // the previous level's projection reach (-1: not projected)
    std::optional<LodMaterial> tile;  // the tiled levels' one material, baked at the first of them
    // The previous level's page before its gutters were widened (texels): the next level's cap.
    std::optional<std::array<int, 2>> capPage;
    PackedPages pages;  // the levels' pages, by charts and options
};

// Builds level k after levels 0 .. k-1: its report res.reports[k] (the plan's figures, page,
// bake), its mesh and material in res.levels (none for LOD0 with Lod0::Original, whose page is
// packed only to cap LOD1's), `groups` (per level triangle, back faces included: its draw group;
// only when in.split has several) and `time`.
void buildLevel(const ChainInputs& in, size_t k, ChainCarry& carry, PackResult& res, std::vector<uint32_t>& groups,
                PackLevelProfile& time);

}  // namespace lodbake::lod_detail

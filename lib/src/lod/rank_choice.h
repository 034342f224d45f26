// Choosing a level's texture layout (T0 or a rank of the texture hierarchy) by the texture
// deviation its bake shows, not by the mapping energy E.
//
// texture-refine's ranks lower the mapping energy E, but their extra charts bring seams and
// gutters that a renderer's bilinear taps read across, and a page of more, smaller charts holds
// fewer texels of surface. Which layout renders better is therefore measured, not assumed: every
// candidate's page is baked (at a reduced size, for cost) and read back the way a renderer reads
// it, bilinearly at the level triangles' page UVs, at sample points spread over the level's
// surface. The reference is a probe bake of the same points, each one a texel strictly inside its
// triangle's own cell of a probe page, so no seam or gutter reaches it. The candidate whose
// read-back lies closest to the probe wins, by more than the estimate can resolve (kScoreMargin)
// over the energy rule's pick.
// \bug The read-back is at the page's finest level (magnified, as up close); a level seen smaller
//      reads coarser mips, where a layout of less stretch can render better than its score says
//      (docs/pack.md, "Choosing the layout by the bake").
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "lodbake/bake/bake.h"
#include "lodbake/core/math.h"

namespace lodbake::lod_detail {

struct ProbeOptions {
    // Probe page side cap, texels (square); it holds (side / cell)^2 cells: at most 4,096 sampled
    // triangles and about 25,000 samples, plenty for an RMS, in a bake of 64k texels.
    int maxSide = 256;
    int minCell = 4;    // smallest cell side, texels: 6 samples per triangle (i + j <= cell - 2)
    int maxCell = 32;   // largest cell side (few triangles: up to 496 samples each)
};

// Sample points on a level's triangles and the probe page that shows the original at them. A cell
// is a square of `cell` texels holding one level triangle as its lower-left half; its samples are
// the texels whose centres lie strictly inside that half. More triangles than cells: every
// stride-th triangle (in index order) gets a cell, and its samples weigh for the skipped ones.
struct ProbeLayout {
    int side = 0, cell = 0;                  // probe page side and cell side, texels
    std::vector<uint32_t> triangles;         // per cell: the level triangle it holds
    std::vector<std::array<Vec2, 3>> uv;     // per cell: the triangle's corners on the probe page ([0,1], v down)
    struct Sample {
        uint32_t triangle = 0;               // level triangle
        std::array<double, 3> bary{};        // of the sample point on it
        uint32_t texel = 0;                  // probe texel (row-major, top row first)
        double weight = 0;                   // 3D area the sample stands for
    };
    std::vector<Sample> samples;
};

// \pre triangles non-empty. The layout depends on the triangles' areas and count only.
ProbeLayout probeLayout(const std::vector<std::array<Vec3, 3>>& triangles, const ProbeOptions& options = {});

// A bake target whose frames are the object's axes (normal +z, tangent +x, bitangent +y) on
// triangles `uv` (bake convention): the normal channel baked for it holds object-space normals,
// which pages with different tangent frames (the probe's and each candidate's) can be compared in.
BakeTarget objectSpaceTarget(std::vector<std::array<Vec2, 3>> uv);

// A baked page as a renderer reads it: RGB floats per texel (encoded values in [0,1]), top row first.
struct PageChannels {
    int width = 0, height = 0;
    const std::vector<float>* color = nullptr;
    const std::vector<float>* normal = nullptr;  // null: not compared
};

// RMS differences per component (encoded [0,1] values), area-weighted over the samples; score =
// sqrt of the mean of the compared channels' mean squares (lower is better).
struct TextureDeviation {
    double color = 0, normal = 0, score = 0;
};

// `page` read bilinearly (texel centres at (x + 0.5) / width, clamped at the border) at every
// sample's point, its UV interpolated from `pageUV` (per level triangle, [0,1], v down), against
// the probe's texel there. The normal is compared when both pages have one.
TextureDeviation textureDeviation(const ProbeLayout& probe, const PageChannels& probePage, const PageChannels& page,
                                  const std::vector<std::array<Vec2, 3>>& pageUV);

// One layout a level could wear, as scored.
struct RankCandidate {
    uint32_t rank = 0;            // 0 = T0
    TextureDeviation deviation;
    int width = 0, height = 0;    // the scored (reduced) page
    size_t charts = 0;
};

// The candidate with the lowest score; a tie goes to the earlier one (candidates in rank order:
// fewer charts). \pre candidates non-empty.
size_t bestCandidate(const std::vector<RankCandidate>& candidates);

// Scores closer than this (relative) are within what the reduced bake can tell apart: a smaller
// lead does not predict which page renders better, so the energy rule's pick stands.
constexpr double kScoreMargin = 0.02;

// The choice: the best candidate, unless the one of rank `byEnergy` (the energy rule's pick)
// scores within `margin` of it, which then stays. \pre candidates non-empty.
size_t chooseCandidate(const std::vector<RankCandidate>& candidates, uint32_t byEnergy, double margin = kScoreMargin);

// Why `chosen` won, for the report: against the rank the energy rule picks (`byEnergy`).
std::string choiceReason(const std::vector<RankCandidate>& candidates, size_t chosen, uint32_t byEnergy);

}  // namespace lodbake::lod_detail

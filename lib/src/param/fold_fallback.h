// The fold fallback of parameterize: what is done when a chart map cannot keep every triangle
// injective. A level triangle still folded in the packed atlas, or crossing a chart boundary, gets
// an island of its own (LevelIsland: the 3D triangle laid flat, baked from the closest original
// surface); an original face still folded leaves its chart as a single-face chart ("carved"), as do
// the faces of a chart the solver could not map; sliver faces that flip once their UVs are rounded
// to float get a corner nudged by a float step.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "lodbake/param/parameterize.h"
#include "param/atlas_layout.h"
#include "param/chart_extraction.h"

namespace lodbake::param_detail {

// glTF stores UVs as floats: an original face that is a sliver in 3D (hence in UV) can come out
// flat or flipped once its corner UVs are rounded to float, whatever their double values. Such a
// face's corner opposite its longest (rounded) edge is moved on a grid of 2^-24 steps (one float
// step for UVs in [0.5, 1), below the overlap tolerance of the checks) in the first of eight
// directions, up to eight steps out, that makes the rounded triangle face the right way. Only this
// face's corner UVs change (cornerUV holds UVs per face corner, nothing is shared); returns the
// faces nudged. `pack` has its own repair for its indexed float meshes (lod/level_mesh.cpp).
size_t nudgeRoundedSliverCorners(const TriMesh& mesh, const std::vector<int32_t>& faceChart, std::vector<std::array<Vec2, 3>>& cornerUV);

// The fallback for faces no chart map keeps injective: each face in `faces` (ascending) leaves its
// chart and becomes a single-face chart appended after the existing ones (a face that already is
// one is laid out again with `minSize`). The chart it leaves keeps its map for its other faces.
// Returns the UV area (model units^2) the new charts add.
double carveFaces(const TriMesh& mesh, const std::vector<uint32_t>& faces, double minSize, std::vector<LocalChart>& charts,
                  ParameterizeResult& res);

// (3b) A chart the solver could not map at all (not a disk after all, a singular Tutte system):
// its faces become single-face charts, laid out at about 2 texels a side of the expected density.
void splitFailedCharts(const TriMesh& mesh, const ParameterizeOptions& options, std::vector<LocalChart>& charts,
                       ParameterizeResult& res);

// Original faces folded in the packed atlas, checked as the tool checks them (float UVs, overlap
// tolerance 1e-7): every flipped face and, of each overlapping pair, the one with the smaller 3D
// area (ascending face ids). Sets res.flips and res.overlaps to the counts. On `threads` threads,
// the same faces for any count.
std::vector<uint32_t> foldedAtlasFaces(const TriMesh& mesh, int threads, ParameterizeResult& res);

// Crossing islands only while their smallest footprint (2 texels plus the gutter a side) fits in
// a quarter of the atlas; beyond that (thousands of tiny crossing triangles) they would crush the
// charts' density and float precision. Records the skipped count; returns whether they are made.
bool crossingIslandsFit(const Multires& multires, const AtlasState& st, const ParameterizeOptions& options, ParameterizeResult& res);

// Checks every level in the atlas as the tool does (float UVs, overlap tolerance 1e-7) and gives
// an island to each level triangle that is flipped, crossing (with `crossing`), or the one of an
// overlapping pair with more projected corners (it straddles a chart cut), else the smaller.
// Islands are laid out at density d (at least 2 texels a side). Returns the islands added. On
// `threads` threads, the same islands for any count.
size_t addFoldIslands(const TriMesh& mesh, const Multires& multires, const std::vector<LocalChart>& charts, bool crossing,
                      double d, int threads, AtlasState& st, ParameterizeResult& res);

}  // namespace lodbake::param_detail

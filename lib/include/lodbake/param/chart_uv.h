// Per-chart UV maps: the injective initial map (Tutte) and the multiresolution-aware energy
// minimisation (thesis 3.3.2-3.3.3, DESIGN.md "The energy parameterize minimises").
//
// A chart is given as its own small mesh: local positions and CCW triangles (indices into
// `positions`). UVs are in model units (area-matched to 3D), math orientation (v up) with
// counter-clockwise triangles having a positive determinant.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "lodbake/core/math.h"
#include "lodbake/core/mesh.h"

namespace lodbake {

// A point of the chart given by up to three chart vertices: UV = sum_k weight[k] uv[vertex[k]].
struct ChartPoint {
    std::array<uint32_t, 3> vertex{};
    std::array<double, 3> weight{1, 0, 0};
};

// A triangle of a simplified level that lies in the chart: its corners are chart vertices or,
// when a collapse moved a corner across the chart boundary, the closest point of the chart
// surface. Its UV triangle must stay positively oriented as well (every level is injective).
struct ChartLevelTriangle {
    std::array<ChartPoint, 3> corner{};
    double area2 = 0;  // |(V_j - V_i) x (V_k - V_i)| of the level triangle, model units
    uint32_t level = 0;  // the Multires level (1-based) it belongs to
};

struct ChartMesh {
    std::vector<Vec3> positions;
    std::vector<Tri> triangles;
    std::vector<ChartLevelTriangle> levelTriangles;  // may be empty
};

// Tutte embedding: the boundary loop goes onto a circle by arc length, interior vertices solve the
// mean-value-weight Laplace system (uniform weights where a mean-value weight is not finite).
// Injective for a disk. The result is then scaled so the total UV area equals the 3D area.
// \throw Impossible when the chart is not a disk (no single boundary loop).
std::vector<Vec2> tutteEmbedding(const ChartMesh& chart);

// Least-squares conformal map (Lévy et al. 2002) with two far-apart boundary vertices pinned, then
// oriented counter-clockwise and scaled so the total UV area equals the 3D area. Its boundary is
// free, so it is not guaranteed injective: check countFlips / countOverlaps before using it.
// \throw Impossible when the chart has no boundary; SolverError when the system is singular (a
// vertex no non-degenerate triangle constrains).
std::vector<Vec2> lscmEmbedding(const ChartMesh& chart);

// A simplification pair restricted to one chart (indices are local vertices of the chart).
struct ChartPair {
    uint32_t vertex = 0;
    std::array<uint32_t, 3> coarse{};
    std::array<double, 3> bary{};
    double deviation = 0;  // |V_i - P_i|, model units
};

struct ChartEnergyOptions {
    double alpha = 0.8;       // E_pixel = r (alpha E_l + (1 - alpha) E_s)
    double beta = 0.7;        // E = beta E_pixel + (1 - beta) E_poly
    double resolution = 1;    // r: 1 at 512^2 texels, 1/4 per 4x texels
    // |V_i - P_i| is clamped below by this fraction of sqrt(chart 3D area) in E_poly.
    double deviationFloor = 0.01;
};

struct ChartEnergy {
    double E = 0, pixel = 0, poly = 0, edge = 0, area = 0;  // pixel = r(a El + (1-a) Es), poly = r sum
};

// E and its terms for `uv` (one UV per chart vertex).
ChartEnergy chartEnergy(const ChartMesh& chart, const std::vector<ChartPair>& pairs, const std::vector<Vec2>& uv,
                        const ChartEnergyOptions& options = {});

// Charts above this many vertices are large: their Ceres steps are solved by conjugate gradients
// (a sparse Cholesky factor fills in: the pairs and level triangles couple far-apart vertices) and
// take at most kLargeChartIterations iterations per solve. From the LSCM start a large chart's E
// falls by a few percent at most in a full solve (docs/benchmarks.md), while each iteration costs
// time in proportion to the chart.
constexpr size_t kLargeChartVertices = 1000;
constexpr int kLargeChartIterations = 10;
// Above this many vertices an injective LSCM start is kept as it is: the solve lowered such
// charts' E by 2% at most while its problem was parameterize's time and memory peak.
constexpr size_t kKeepLscmAboveVertices = 20000;

struct ChartSolveOptions {
    ChartEnergyOptions energy;
    int maxIterations = 50;  // Ceres iterations per solve; 0 = keep the initial map
    // Solves while flipped level triangles remain (each adds their penalties to the next one), at
    // most this many (>= 1). More rounds cost time in proportion and leave about as many folded
    // level triangles, which parameterize then gives islands anyway.
    int levelRounds = 2;
};

struct ChartSolveResult {
    std::vector<Vec2> uv;
    ChartEnergy before, after;
    int iterations = 0;
    size_t levelFlipsBefore = 0, levelFlipsAfter = 0;  // countLevelFlips of initial and uv
    // The solver lowered the level flip count, or kept it and lowered E (else uv == the initial map).
    bool improved = false;
};

// Minimises E with Ceres (Levenberg-Marquardt, 1 thread) from `initial`, which must be injective
// (every triangle's UV determinant > 0). Steps that would fold a triangle are rejected, so the
// result has no flipped triangle; overlaps of the boundary are not prevented (check with
// countOverlaps). Level triangles (chart.levelTriangles) positive at the start are guarded the
// same way; flipped ones get a hinge penalty pulling their determinant above 5% of their 3D
// area, and the solve is repeated (up to options.levelRounds rounds) while that lowers their flip count.
// Deterministic.
ChartSolveResult optimizeChartUV(const ChartMesh& chart, const std::vector<ChartPair>& pairs,
                                 const std::vector<Vec2>& initial, const ChartSolveOptions& options = {});

// Triangles whose UV determinant is <= 0.
size_t countFlips(const ChartMesh& chart, const std::vector<Vec2>& uv);
// UV of a chart point.
Vec2 chartPointUV(const ChartPoint& p, const std::vector<Vec2>& uv);
// Level triangles (chart.levelTriangles) whose UV determinant is <= 0.
size_t countLevelFlips(const ChartMesh& chart, const std::vector<Vec2>& uv);
// Triangles owning a boundary edge that properly intersects another boundary edge of the chart
// (sort-and-sweep over the boundary edges). 0 together with 0 flips means the map is injective.
size_t countOverlaps(const ChartMesh& chart, const std::vector<Vec2>& uv);

}  // namespace lodbake

// Texture deviation of a level (thesis 3.3.2, "polygon-resolution error" measured): the distance
// between a point p on a level triangle and the original surface point q that the same texel
// shows in the atlas. p has the UV u interpolated from the level's corner UVs; q is the point of
// the original faces of the same chart whose atlas UV is u (point location in the chart's UV
// triangulation through a uniform grid; when u falls outside every original triangle of the
// chart, the UV-closest point of the chart is used and counted as `outside`).
//
// Samples are area-weighted and deterministic: triangle t gets round(cumulative share) points
// placed by the R2 low-discrepancy sequence (Roberts 2018) warped onto the triangle. Triangles
// are measured in parallel and summed in triangle order (the same figures for any thread count).
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "lodbake/chart/level_charts.h"
#include "lodbake/core/closest_point.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/face_tree.h"
#include "lodbake/core/grid2d.h"
#include "lodbake/core/parallel.h"
#include "lodbake/param/parameterize.h"

namespace lodbake {
namespace {

// Interleaved bits of two 10-bit coordinates: nearby (x, y) get nearby keys.
uint32_t mortonKey(uint32_t x, uint32_t y) {
    uint32_t key = 0;
    for (uint32_t b = 0; b < 10; ++b) key |= ((x >> b) & 1u) << (2 * b) | ((y >> b) & 1u) << (2 * b + 1);
    return key;
}

// The used original faces in a grid over the unit square of about one cell per face (faces
// outside it land in the border cells), filled on `threads` threads.
Grid2 uvGrid(const std::vector<std::array<Vec2, 3>>& uv, const std::vector<char>& use, int threads) {
    std::vector<GridItem2> items;
    items.reserve(uv.size());
    for (size_t f = 0; f < uv.size(); ++f) {
        if (!use[f]) continue;
        const auto& t = uv[f];
        items.push_back({uint32_t(f), {std::min({t[0].x, t[1].x, t[2].x}), std::min({t[0].y, t[1].y, t[2].y})},
                         {std::max({t[0].x, t[1].x, t[2].x}), std::max({t[0].y, t[1].y, t[2].y})}});
    }
    const int g = std::clamp(int(std::sqrt(double(items.size()))), 1, 1024);
    return Grid2({0, 0}, {1, 1}, g, g, items, threads);
}

}  // namespace

TextureDeviation textureDeviation(const TriMesh& mesh, const Level& level, const ChartLayout& layout,
                                  const TextureDeviationOptions& options) {
    const size_t nf = mesh.triangleCount();
    if (layout.faceChart.size() != nf || layout.cornerUV.size() != nf)
        throw InvalidInput("textureDeviation: chart layout does not match the mesh");
    if (level.faces.size() != level.triangles.size() || level.cornerWedges.size() != level.triangles.size())
        throw InvalidInput("textureDeviation: level faces, triangles and corners differ in size");
    TextureDeviation res;
    res.diagonal = bounds(mesh).diagonal();
    std::vector<char> use(nf, 0);
    for (size_t f = 0; f < nf; ++f) {
        const Tri& t = mesh.triangles[f];
        use[f] = t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
    }
    const Grid2 grid = uvGrid(layout.cornerUV, use, options.threads);

    const std::vector<uint32_t> triChart = levelTriangleCharts(mesh, layout.faceChart, layout.chartCount, level);
    std::map<Tri, size_t> islandOf;
    if (options.islands)
        for (size_t i = 0; i < options.islands->size(); ++i) islandOf.emplace((*options.islands)[i].vertices, i);
    // Area-weighted sample counts (cumulative rounding: deterministic, total = options.samples).
    std::vector<double> area(level.triangles.size());
    double total = 0;
    for (size_t t = 0; t < area.size(); ++t) {
        const Tri& v = level.triangles[t];
        area[t] = triangleArea(mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]]);
        total += area[t];
    }
    if (!(total > 0) || options.samples == 0) return res;
    // Samples per triangle and the index of its first sample in the R2 sequence.
    std::vector<size_t> count(area.size()), first(area.size());
    double acc = 0;
    size_t emitted = 0;
    for (size_t t = 0; t < area.size(); ++t) {
        acc += area[t] / total * double(options.samples);
        count[t] = size_t(std::llround(acc)) - emitted;
        first[t] = emitted;
        emitted += count[t];
    }
    // Island triangles: the faces that can hold the closest point of any of their points, as a
    // tree, built (in parallel) only for the islands that get samples at this level.
    std::vector<char> sampled(options.islands ? options.islands->size() : 0, 0);
    for (size_t t = 0; t < area.size(); ++t)
        if (count[t] > 0)
            if (auto it = islandOf.find(level.triangles[t]); it != islandOf.end()) sampled[it->second] = 1;
    std::vector<std::unique_ptr<FaceTree>> islandNear(sampled.size());
    parallelFor(sampled.size(), options.threads, [&](size_t i) {
        if (!sampled[i]) return;
        const LevelIsland& isl = (*options.islands)[i];
        islandNear[i] = std::make_unique<FaceTree>(
            mesh, facesNearTriangle(mesh, isl.faces, {mesh.positions[isl.vertices[0]], mesh.positions[isl.vertices[1]],
                                                      mesh.positions[isl.vertices[2]]}));
    });
    // Triangles are measured on options.threads threads into their own slots, then summed in
    // triangle order: the figures do not depend on the thread count.
    struct Partial {
        double sum = 0, sum2 = 0, max = 0;
        size_t samples = 0, islandSamples = 0, outside = 0;
    };
    std::vector<Partial> part(area.size());
    const double g1 = 1.32471795724474602596, a1 = 1 / g1, a2 = 1 / (g1 * g1);  // R2 sequence
    parallelFor(area.size(), options.threads, [&](size_t t) {
        Partial& out = part[t];
        const Tri& v = level.triangles[t];
        std::array<Vec2, 3> luv{};
        for (size_t k = 0; k < 3; ++k) {
            uint32_t w = level.cornerWedges[t][k];
            luv[k] = w < mesh.wedges.uv0.size() ? mesh.wedges.uv0[w] : Vec2{};
        }
        const uint32_t chart = triChart[t];
        auto isl = islandOf.find(v);
        uint32_t islandHint = UINT32_MAX;  // the previous island sample's answer: the next one's start
        auto add = [&](double d) {
            out.sum += d;
            out.sum2 += d * d;
            out.max = std::max(out.max, d);
            ++out.samples;
        };
        auto r2Point = [&](size_t seq) {
            return std::array<double, 2>{fractionalPart(0.5 + a1 * double(seq + 1)), fractionalPart(0.5 + a2 * double(seq + 1))};
        };
        auto samplePoint = [&](size_t seq, Vec3& p, Vec2& u) {
            const auto [r1, r2] = r2Point(seq);
            double sq = std::sqrt(r1);
            std::array<double, 3> b{1 - sq, sq * (1 - r2), sq * r2};
            p = mesh.positions[v[0]] * b[0] + mesh.positions[v[1]] * b[1] + mesh.positions[v[2]] * b[2];
            u = luv[0] * b[0] + luv[1] * b[1] + luv[2] * b[2];
        };
        if (isl != islandOf.end()) {
            // An island texel shows the closest point of the island's faces (the bake's rule).
            // The samples are queried in Morton order of their sequence coordinates, so each
            // query's hint (the previous answer) lies next to it; the answers do not depend on
            // the hint, and they are summed in sequence order, so the figures are unchanged.
            std::vector<std::pair<uint32_t, uint32_t>> order(count[t]);
            for (size_t s = 0; s < count[t]; ++s) {
                const auto [r1, r2] = r2Point(first[t] + s);
                order[s] = {mortonKey(uint32_t(r1 * 1024), uint32_t(r2 * 1024)), uint32_t(s)};
            }
            std::sort(order.begin(), order.end());
            std::vector<double> dist(count[t], 1e300);
            for (const auto& [key, s] : order) {
                Vec3 p;
                Vec2 u;
                samplePoint(first[t] + s, p, u);
                std::array<double, 3> w{};
                uint32_t islandFace = 0;
                dist[s] = islandNear[isl->second]->closest(p, islandFace, w, islandHint);
            }
            for (double dmin : dist) {
                if (!(dmin < 1e300)) continue;
                add(std::sqrt(dmin));
                ++out.islandSamples;
            }
            return;
        }
        for (size_t s = 0, seq = first[t]; s < count[t]; ++s, ++seq) {
            Vec3 p;
            Vec2 u;
            samplePoint(seq, p, u);
            // Point location in the chart's original triangles; else the UV-closest one nearby.
            double best = 1e300;
            uint32_t bestFace = UINT32_MAX;
            std::array<double, 3> bestW{};
            const int g = grid.nx(), cx = grid.cellX(u.x), cy = grid.cellY(u.y);
            int lastRing = g;  // after the first hit off the chart, one more ring is searched
            for (int ring = 0; ring < g && ring <= lastRing; ++ring) {
                for (int y = std::max(0, cy - ring); y <= std::min(g - 1, cy + ring); ++y)
                    for (int x = std::max(0, cx - ring); x <= std::min(g - 1, cx + ring); ++x) {
                        if (std::max(std::abs(x - cx), std::abs(y - cy)) != ring) continue;
                        for (uint32_t f : grid.cell(x, y)) {
                            if (layout.faceChart[f] != chart) continue;
                            std::array<double, 3> w{};
                            double d = closestOnTriangle(u, layout.cornerUV[f], w);
                            if (d < best || (d == best && f < bestFace)) {
                                best = d;
                                bestFace = f;
                                bestW = w;
                            }
                        }
                    }
                if (best == 0) break;
                if (bestFace != UINT32_MAX && lastRing == g) lastRing = ring + 1;
            }
            if (bestFace == UINT32_MAX) continue;
            if (best > 0) ++out.outside;
            const Tri& o = mesh.triangles[bestFace];
            Vec3 q = mesh.positions[o[0]] * bestW[0] + mesh.positions[o[1]] * bestW[1] + mesh.positions[o[2]] * bestW[2];
            add(length(p - q));
        }
    });
    double sum = 0, sum2 = 0;
    for (const Partial& q : part) {
        sum += q.sum;
        sum2 += q.sum2;
        res.max = std::max(res.max, q.max);
        res.samples += q.samples;
        res.islandSamples += q.islandSamples;
        res.outside += q.outside;
    }
    if (res.samples > 0) {
        res.mean = sum / double(res.samples);
        res.rms = std::sqrt(sum2 / double(res.samples));
    }
    if (res.diagonal > 0) {
        res.meanRelative = res.mean / res.diagonal;
        res.maxRelative = res.max / res.diagonal;
    }
    return res;
}

}  // namespace lodbake

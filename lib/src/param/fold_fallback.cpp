// The fold fallback of parameterize (fold_fallback.h): level islands, carved single-face charts,
// failed charts split into faces, and the float-rounding repair of sliver faces.
#include "param/fold_fallback.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "lodbake/core/closest_point.h"
#include "lodbake/core/math.h"
#include "param/uv_check_detail.h"

namespace lodbake::param_detail {
namespace {

// Model-unit UVs of a level triangle's island: the 3D triangle laid flat (A at the origin, B on
// +u, C above), each side and the height at least `minSize` so the island keeps texels and a
// positive float area. Counter-clockwise.
std::vector<Vec2> islandLayout(Vec3 a, Vec3 b, Vec3 c, double minSize) {
    Vec3 ab = b - a, ac = c - a;
    double lab = length(ab);
    double x = lab > 0 ? dot(ac, ab) / lab : 0;
    double y = lab > 0 ? length(cross(ab, ac)) / lab : length(ac);
    lab = std::max(lab, minSize);
    y = std::max(y, minSize);
    return {Vec2{0, 0}, Vec2{lab, 0}, Vec2{x, y}};
}

// A chart of one original face, laid flat by islandLayout (injective by construction).
LocalChart singleFaceChart(const TriMesh& mesh, uint32_t f, double minSize) {
    LocalChart c;
    const Tri& t = mesh.triangles[f];
    c.faces = {f};
    c.vertices = {t[0], t[1], t[2]};
    std::sort(c.vertices.begin(), c.vertices.end());
    for (uint32_t i = 0; i < 3; ++i) {
        c.local.emplace(c.vertices[i], i);
        c.mesh.positions.push_back(mesh.positions[c.vertices[i]]);
    }
    c.mesh.triangles.push_back({c.local[t[0]], c.local[t[1]], c.local[t[2]]});
    std::vector<Vec2> flat = islandLayout(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]], minSize);
    c.uv.assign(3, {});
    for (size_t k = 0; k < 3; ++k) c.uv[c.local[t[k]]] = flat[k];
    return c;
}

// Charts emptied by carveFaces are dropped and the rest renumbered in order (chart ids stay dense).
void dropEmptyCharts(std::vector<LocalChart>& charts, ParameterizeResult& res) {
    std::vector<int32_t> newId(charts.size(), -1);
    size_t n = 0;
    for (size_t c = 0; c < charts.size(); ++c)
        if (!charts[c].faces.empty() || res.chartReports[c].method != "failed") newId[c] = int32_t(n++);
    if (n == charts.size()) return;
    for (int32_t& c : res.charts.faceChart)
        if (c >= 0) c = newId[size_t(c)];
    for (size_t c = 0; c < charts.size(); ++c)
        if (newId[c] >= 0 && size_t(newId[c]) != c) {
            charts[size_t(newId[c])] = std::move(charts[c]);
            res.chartReports[size_t(newId[c])] = std::move(res.chartReports[c]);
        }
    charts.resize(n);
    res.chartReports.resize(n);
    res.charts.chartCount = uint32_t(n);
}

// The faces an island's bake and deviation sample: exactly facesNearTriangle(candidates, triangle)
// with `candidates` the faces of charts `cs` (ascending ids, each chart's faces as charts[c].faces
// holds them), found without listing the charts' faces or scanning them all. The triangle's own
// face, when a candidate, bounds the centroid's distance to the candidates from above, so only
// candidates whose boxes lie within that bound's reach (a superset of facesNearTriangle's, which
// holds the closest face) are kept, looked up in the face grid; the ones within the true reach are
// the same faces in the same order. Later calls of facesNearTriangle on the result return it
// unchanged.
std::vector<uint32_t> islandFaces(const TriMesh& mesh, const std::vector<LocalChart>& charts, const std::vector<int32_t>& faceChart,
                                  const FaceGrid& grid, const std::vector<uint32_t>& cs, const Tri& v, uint32_t ownFace) {
    const std::array<Vec3, 3> tri{mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]]};
    // A candidate: a face with a chart among cs that is not index-degenerate (charts hold no such
    // face, and the grid leaves them out).
    auto candidate = [&](uint32_t f) {
        return faceChart[f] >= 0 && std::binary_search(cs.begin(), cs.end(), uint32_t(faceChart[f])) &&
               !degenerateIndices(mesh.triangles[f]);
    };
    if (!candidate(ownFace)) {
        std::vector<uint32_t> candidates;
        for (uint32_t c : cs) candidates.insert(candidates.end(), charts[c].faces.begin(), charts[c].faces.end());
        std::sort(candidates.begin(), candidates.end());
        return facesNearTriangle(mesh, candidates, tri);
    }
    const Vec3 c = (tri[0] + tri[1] + tri[2]) * (1.0 / 3);
    const Tri& o = mesh.triangles[ownFace];
    const auto b = closestOnTriangle(c, mesh.positions[o[0]], mesh.positions[o[1]], mesh.positions[o[2]]);
    const Vec3 q = mesh.positions[o[0]] * b[0] + mesh.positions[o[1]] * b[1] + mesh.positions[o[2]] * b[2];
    double r = 0;
    for (const Vec3& p : tri) r = std::max(r, length(p - c));
    // Twice facesNearTriangle's margin: the bound's reach is never below the true one.
    const double reach = (length(q - c) + 2 * r) * (1 + 2e-9) + 2e-12;
    // The grid box is padded past the reach so rounding of its corners never drops a face the
    // exact box-distance test keeps.
    const double pad = reach * (1 + 1e-6) + 1e-9 * (1 + std::abs(c.x) + std::abs(c.y) + std::abs(c.z));
    std::vector<uint32_t> near;
    auto keep = [&](uint32_t f) {
        if (candidate(f) && boxDistance2(faceBox(mesh, f), c) <= reach * reach) near.push_back(f);
    };
    // A face within the reach has its box inside the padded box: the grid's faces there, or the
    // charts' own faces when they are fewer than the grid cells' entries (a coarse level's large
    // triangle over small charts), give the same faces.
    const Vec3 lo = c - Vec3{pad, pad, pad}, hi = c + Vec3{pad, pad, pad};
    size_t chartFaces = 0;
    for (uint32_t k : cs) chartFaces += charts[k].faces.size();
    if (chartFaces < grid.entriesIn(lo, hi)) {
        for (uint32_t k : cs)
            for (uint32_t f : charts[k].faces) keep(f);
        std::sort(near.begin(), near.end());
    } else {
        for (uint32_t f : grid.facesIn(lo, hi)) keep(f);
    }
    return facesNearTriangle(mesh, near, tri);
}

}  // namespace

size_t nudgeRoundedSliverCorners(const TriMesh& mesh, const std::vector<int32_t>& faceChart, std::vector<std::array<Vec2, 3>>& cornerUV) {
    auto rounded = [](Vec2 p) { return Vec2{double(float(p.x)), double(float(p.y))}; };
    auto area = [&](const std::array<Vec2, 3>& t) {  // math orientation (v up) of glTF UVs
        Vec2 a = rounded(t[0]), b = rounded(t[1]), c = rounded(t[2]);
        a.y = -a.y;
        b.y = -b.y;
        c.y = -c.y;
        return cross(b - a, c - a);
    };
    constexpr double kStep = 1.0 / 16777216.0;  // 2^-24: one float step for UVs in [0.5, 1)
    const Vec2 dirs[8] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
    size_t repaired = 0;
    for (size_t f = 0; f < cornerUV.size(); ++f) {
        if (faceChart[f] < 0 || degenerateIndices(mesh.triangles[f]) || area(cornerUV[f]) > 0) continue;
        std::array<Vec2, 3>& t = cornerUV[f];
        const size_t apex = cornerOppositeLongestEdge({rounded(t[0]), rounded(t[1]), rounded(t[2])});
        bool done = false;
        for (int step = 1; step <= 8 && !done; ++step)
            for (const Vec2& dir : dirs) {
                std::array<Vec2, 3> c = t;
                c[apex] = rounded(t[apex]) + dir * (step * kStep);
                if (area(c) > 0) {
                    t = c;
                    done = true;
                    break;
                }
            }
        if (done) ++repaired;
    }
    return repaired;
}

double carveFaces(const TriMesh& mesh, const std::vector<uint32_t>& faces, double minSize, std::vector<LocalChart>& charts,
                  ParameterizeResult& res) {
    double addedArea = 0;
    for (uint32_t f : faces) {
        const int32_t old = res.charts.faceChart[f];
        if (old < 0) continue;
        LocalChart& from = charts[size_t(old)];
        if (from.faces.size() == 1) {
            from = singleFaceChart(mesh, f, minSize);
            continue;
        }
        auto it = std::find(from.faces.begin(), from.faces.end(), f);
        if (it == from.faces.end()) continue;
        const size_t i = size_t(it - from.faces.begin());
        from.faces.erase(it);
        from.mesh.triangles.erase(from.mesh.triangles.begin() + long(i));
        if (from.faces.empty()) from.uv.clear();
        LocalChart c = singleFaceChart(mesh, f, minSize);
        addedArea += triangleArea(c.uv[0], c.uv[1], c.uv[2]);
        res.charts.faceChart[f] = int32_t(charts.size());
        ChartReport rep;
        rep.faces = 1;
        rep.vertices = 3;
        rep.method = "single-face";
        res.chartReports.push_back(rep);
        charts.push_back(std::move(c));
        ++res.carvedFaces;
    }
    res.charts.chartCount = uint32_t(charts.size());
    return addedArea;
}

void splitFailedCharts(const TriMesh& mesh, const ParameterizeOptions& options, std::vector<LocalChart>& charts,
                       ParameterizeResult& res) {
    std::vector<uint32_t> faces;
    for (size_t c = 0; c < charts.size(); ++c) {
        if (res.chartReports[c].method != "failed") continue;
        ++res.failedCharts;
        res.warnings.push_back("chart " + std::to_string(c) + " (" + std::to_string(charts[c].faces.size()) +
                               " faces) could not be flattened (" + res.chartReports[c].failure +
                               "); its faces are laid out one by one");
        faces.insert(faces.end(), charts[c].faces.begin(), charts[c].faces.end());
    }
    if (faces.empty()) return;
    std::sort(faces.begin(), faces.end());
    const double area = surfaceArea(mesh);
    const double expectedDensity = 0.7 * options.textureSize / std::sqrt(std::max(area, 1e-30));
    carveFaces(mesh, faces, 2.0 / expectedDensity, charts, res);
    dropEmptyCharts(charts, res);
}

std::vector<uint32_t> foldedAtlasFaces(const TriMesh& mesh, int threads, ParameterizeResult& res) {
    std::vector<std::array<Vec2, 3>> tris;
    std::vector<uint32_t> which;
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f)
        if (!degenerateIndices(mesh.triangles[f])) {
            tris.push_back(res.cornerUV[f]);
            which.push_back(f);
        }
    param_detail::UVFolds folds = param_detail::findUVFolds(std::move(tris), 1e-7, threads);
    std::vector<char> pick(which.size(), 0);
    res.flips = 0;
    for (size_t i = 0; i < which.size(); ++i) {
        pick[i] = folds.flipped[i];
        res.flips += size_t(folds.flipped[i]);
    }
    auto area3 = [&](uint32_t f) {
        const Tri& v = mesh.triangles[f];
        return triangleArea(mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]]);
    };
    std::set<uint32_t> overlapping;
    for (const auto& [i, j] : folds.overlapping) {
        overlapping.insert(i);
        overlapping.insert(j);
        if (pick[i] || pick[j]) continue;
        pick[area3(which[i]) <= area3(which[j]) ? i : j] = 1;
    }
    res.overlaps = overlapping.size();
    std::vector<uint32_t> faces;
    for (size_t i = 0; i < which.size(); ++i)
        if (pick[i]) faces.push_back(which[i]);
    return faces;
}

bool crossingIslandsFit(const Multires& multires, const AtlasState& st, const ParameterizeOptions& options, ParameterizeResult& res) {
    std::set<Tri> crossingTriples;
    for (size_t li = 0; li < multires.levels.size(); ++li)
        for (size_t t = 0; t < multires.levels[li].triangles.size(); ++t)
            if (st.projectedCount[li][t] > 0) crossingTriples.insert(multires.levels[li].triangles[t]);
    const double footprint = std::pow(2.0 + options.gutter, 2.0);
    const int size = options.textureSize;
    const bool fits = double(crossingTriples.size()) * footprint <= 0.25 * double(size) * double(size);
    res.crossingIslandsSkipped = fits ? 0 : crossingTriples.size();
    return fits;
}

size_t addFoldIslands(const TriMesh& mesh, const Multires& multires, const std::vector<LocalChart>& charts, bool crossing,
                      double d, int threads, AtlasState& st, ParameterizeResult& res) {
    size_t added = 0;
    for (size_t li = 0; li < multires.levels.size(); ++li) {
        const Level& L = multires.levels[li];
        std::vector<std::array<Vec2, 3>> tris;
        std::vector<uint32_t> which;
        for (size_t t = 0; t < L.triangles.size(); ++t) {
            const Tri& v = L.triangles[t];
            if (degenerateIndices(v) || st.islandOf.count(v)) continue;  // islands never overlap a chart
            tris.push_back(res.levels[li].uv[t]);
            which.push_back(uint32_t(t));
        }
        param_detail::UVFolds folds = param_detail::findUVFolds(std::move(tris), 1e-7, threads);
        std::vector<char> pick(which.size(), 0);
        for (size_t i = 0; i < which.size(); ++i)
            pick[i] = folds.flipped[i] || (crossing && st.projectedCount[li][which[i]] > 0);
        auto area3 = [&](uint32_t t) {
            const Tri& v = L.triangles[t];
            return triangleArea(mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]]);
        };
        for (const auto& [i, j] : folds.overlapping) {
            if (pick[i] || pick[j]) continue;
            uint8_t pi = st.projectedCount[li][which[i]], pjc = st.projectedCount[li][which[j]];
            bool takeI = pi != pjc ? pi > pjc : area3(which[i]) < area3(which[j]);
            pick[takeI ? i : j] = 1;
        }
        for (size_t i = 0; i < which.size(); ++i) {
            if (!pick[i]) continue;
            const uint32_t t = which[i];
            const Tri& v = L.triangles[t];
            if (st.islandOf.count(v)) continue;
            st.islandOf.emplace(v, uint32_t(st.islandModel.size()));
            st.islandModel.push_back(islandLayout(mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]], 2.0 / d));
            // The island's bake samples the charts of its face and of its corners.
            LevelIsland isl;
            isl.vertices = v;
            isl.level = uint32_t(li + 1);
            std::vector<uint32_t> cs{st.faceChart[L.faces[t]]};
            for (uint32_t vv : v) cs.insert(cs.end(), st.vertexCharts[vv].begin(), st.vertexCharts[vv].end());
            std::sort(cs.begin(), cs.end());
            cs.erase(std::unique(cs.begin(), cs.end()), cs.end());
            isl.faces = islandFaces(mesh, charts, res.charts.faceChart, st.grid, cs, v, L.faces[t]);
            res.islands.push_back(std::move(isl));
            ++added;
        }
    }
    return added;
}

}  // namespace lodbake::param_detail

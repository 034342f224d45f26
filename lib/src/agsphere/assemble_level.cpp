// A built level as a Multires Level: faces, wedges and pairs (agsphere.h describes the output).
//
//   triangles   kept regions: their original faces; retriangulated regions: each new triangle
//               names the region's face incident to most of its corners, and takes each corner's
//               wedge from that face, else from a face of the region, else from any face
//   pairs       removed interior vertices -> closest point of the region's new triangles;
//               removed run vertices -> closest point of their simplified edge (edge form)
#include "agsphere/assemble_level.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "lodbake/core/closest_point.h"

namespace lodbake::agsphere_detail {
namespace {

// Closest point among triangles (brute force up to 48 triangles, else a uniform grid of at most
// 48 cells per axis).
struct ClosestFinder {
    const Topology& t;
    const std::vector<Tri>& tris;
    Vec3 lo;
    double h = 1;
    int n[3] = {1, 1, 1};
    std::vector<std::vector<uint32_t>> cells;
    std::vector<uint32_t> stamp;
    uint32_t clock = 0;

    ClosestFinder(const Topology& top, const std::vector<Tri>& tr) : t(top), tris(tr) {
        if (tris.size() <= 48) return;
        Box3 b;
        for (const Tri& x : tris)
            for (uint32_t v : x) b.extend(t.P(v));
        lo = b.min;
        Vec3 ext = b.max - b.min;
        double longest = std::max({ext.x, ext.y, ext.z, 1e-300});
        int res = std::clamp(int(std::cbrt(double(tris.size())) * 1.5), 1, 48);
        h = longest / res;
        for (int k = 0; k < 3; ++k) n[k] = std::clamp(int(std::ceil(ext[k] / h)), 1, 48);
        cells.resize(size_t(n[0]) * n[1] * n[2]);
        stamp.assign(tris.size(), 0);
        for (uint32_t i = 0; i < tris.size(); ++i) {
            Box3 tb;
            for (uint32_t v : tris[i]) tb.extend(t.P(v));
            int a[3], z[3];
            for (int k = 0; k < 3; ++k) a[k] = cellOf(tb.min[k], k), z[k] = cellOf(tb.max[k], k);
            for (int x = a[0]; x <= z[0]; ++x)
                for (int y = a[1]; y <= z[1]; ++y)
                    for (int q = a[2]; q <= z[2]; ++q) cells[index(x, y, q)].push_back(i);
        }
    }
    int cellOf(double v, int axis) const { return std::clamp(int(std::floor((v - lo[axis]) / h)), 0, n[axis] - 1); }
    size_t index(int x, int y, int z) const { return (size_t(z) * n[1] + y) * n[0] + x; }

    // Returns the triangle index (the smallest on ties), barycentrics and squared distance.
    uint32_t find(Vec3 p, std::array<double, 3>& bary, double& best) {
        best = std::numeric_limits<double>::infinity();
        uint32_t bi = 0;
        auto test = [&](uint32_t i) {
            const Tri& x = tris[i];
            auto b = closestOnTriangle(p, t.P(x[0]), t.P(x[1]), t.P(x[2]));
            Vec3 q = t.P(x[0]) * b[0] + t.P(x[1]) * b[1] + t.P(x[2]) * b[2];
            double d = length2(q - p);
            if (d < best || (d == best && i < bi)) best = d, bi = i, bary = b;
        };
        if (cells.empty()) {
            for (uint32_t i = 0; i < tris.size(); ++i) test(i);
            return bi;
        }
        ++clock;
        int c[3];
        for (int k = 0; k < 3; ++k) c[k] = cellOf(p[k], k);
        int maxR = std::max({n[0], n[1], n[2]});
        for (int r = 0; r <= maxR; ++r) {
            for (int x = c[0] - r; x <= c[0] + r; ++x)
                for (int y = c[1] - r; y <= c[1] + r; ++y)
                    for (int z = c[2] - r; z <= c[2] + r; ++z) {
                        if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != r) continue;
                        if (x < 0 || y < 0 || z < 0 || x >= n[0] || y >= n[1] || z >= n[2]) continue;
                        for (uint32_t i : cells[index(x, y, z)])
                            if (stamp[i] != clock) stamp[i] = clock, test(i);
                    }
            // Everything not visited lies outside the cube of cells within ring r.
            double lb = std::numeric_limits<double>::infinity();
            for (int k = 0; k < 3; ++k) {
                double lower = lo[k] + (c[k] - r) * h, upper = lo[k] + (c[k] + r + 1) * h;
                lb = std::min({lb, p[k] - lower, upper - p[k]});
            }
            if (lb > 0 && best <= lb * lb) break;
        }
        return bi;
    }
};

// The face of region i incident to most corners of tr (then the smallest id); the region's
// representative when none is.
uint32_t sourceFace(const Topology& t, const Regions& r, uint32_t i, const Tri& tr) {
    uint32_t bestFace = kNone;
    int bestScore = 0;
    for (uint32_t c : tr)
        for (const uint32_t* k = t.vertexFaces.begin(c); k != t.vertexFaces.end(c); ++k) {
            uint32_t f = *k;
            if (r.of[f] != i) continue;
            int score = 0;
            for (uint32_t x : tr) score += (t.T(f)[0] == x) + (t.T(f)[1] == x) + (t.T(f)[2] == x);
            if (score > bestScore || (score == bestScore && f < bestFace)) bestScore = score, bestFace = f;
        }
    return bestFace == kNone ? r.rep[i] : bestFace;
}

// Corner wedges of new triangle tr: from `face`, else from a face of region i at that vertex,
// else from any face there (the last one wins within a face; 0 when none).
Tri cornerWedges(const Topology& t, const Regions& r, uint32_t i, uint32_t face, const Tri& tr) {
    const TriMesh& m = *t.mesh;
    Tri cw{};
    for (int c = 0; c < 3; ++c) {
        uint32_t v = tr[size_t(c)];
        uint32_t wedge = kNone;
        for (int k = 0; k < 3; ++k)
            if (t.T(face)[size_t(k)] == v) wedge = m.cornerWedges[face][size_t(k)];
        for (const uint32_t* k = t.vertexFaces.begin(v); k != t.vertexFaces.end(v) && wedge == kNone; ++k) {
            uint32_t f = *k;
            if (r.of[f] != i) continue;
            for (int j = 0; j < 3; ++j)
                if (t.T(f)[size_t(j)] == v) wedge = m.cornerWedges[f][size_t(j)];
        }
        for (const uint32_t* k = t.vertexFaces.begin(v); k != t.vertexFaces.end(v) && wedge == kNone; ++k) {
            uint32_t f = *k;
            for (int j = 0; j < 3; ++j)
                if (t.T(f)[size_t(j)] == v) wedge = m.cornerWedges[f][size_t(j)];
        }
        cw[size_t(c)] = wedge == kNone ? 0 : wedge;
    }
    return cw;
}

// Level triangles, faces and wedges, region by region; triRegion = region of each triangle.
void addTriangles(const Topology& t, const LevelBuild& L, Level& level, std::vector<uint32_t>& triRegion) {
    const TriMesh& m = *t.mesh;
    const Regions& r = L.regions;
    const bool wedges = m.cornerWedges.size() == m.triangles.size();
    for (uint32_t i = 0; i < r.count(); ++i) {
        const RegionOut& o = L.out[i];
        if (o.state == RegionState::Kept) {
            for (uint32_t k = r.faceOffset[i]; k < r.faceOffset[i + 1]; ++k) {
                uint32_t f = r.faces[k];
                level.faces.push_back(f);
                level.triangles.push_back(m.triangles[f]);
                if (wedges) level.cornerWedges.push_back(m.cornerWedges[f]);
                triRegion.push_back(i);
            }
            continue;
        }
        if (o.state != RegionState::Retriangulated) continue;
        for (const Tri& tr : o.tris) {
            uint32_t face = sourceFace(t, r, i, tr);
            level.faces.push_back(face);
            level.triangles.push_back(tr);
            triRegion.push_back(i);
            if (wedges) level.cornerWedges.push_back(cornerWedges(t, r, i, face, tr));
        }
    }
}

// Pairs of the interior vertices that retriangulated regions removed.
void addInteriorPairs(const Topology& t, const LevelBuild& L, const std::vector<char>& present,
                      const std::vector<uint32_t>& triRegion, Level& level) {
    const Regions& r = L.regions;
    for (uint32_t i = 0; i < r.count(); ++i) {
        if (L.out[i].state != RegionState::Retriangulated) continue;
        std::vector<uint32_t> removed;
        for (uint32_t k = r.faceOffset[i]; k < r.faceOffset[i + 1]; ++k)
            for (uint32_t v : t.T(r.faces[k]))
                if (!present[v] && L.runs.runOf[v] == kNone && !L.runs.junction[v]) removed.push_back(v);
        std::sort(removed.begin(), removed.end());
        removed.erase(std::unique(removed.begin(), removed.end()), removed.end());
        if (removed.empty()) continue;
        const std::vector<Tri>& tris = L.out[i].tris;
        ClosestFinder finder(t, tris);
        // Level triangle index of the region's first triangle (triangles are region-contiguous).
        uint32_t firstTri = uint32_t(std::lower_bound(triRegion.begin(), triRegion.end(), i) - triRegion.begin());
        for (uint32_t v : removed) {
            std::array<double, 3> b{};
            double d2 = 0;
            uint32_t k = finder.find(t.P(v), b, d2);
            SimplificationPair p;
            p.vertex = v;
            p.coarse = tris[k];
            p.bary = {float(b[0]), float(b[1]), float(b[2])};
            p.face = level.faces[firstTri + k];
            Vec3 q = t.P(p.coarse[0]) * p.bary[0] + t.P(p.coarse[1]) * p.bary[1] + t.P(p.coarse[2]) * p.bary[2];
            p.deviation = float(length(t.P(v) - q));
            level.pairs.push_back(p);
        }
    }
}

// Pairs of the run vertices that simplification removed: closest point on their simplified edge,
// named by the level triangle on that edge (else the run's first region).
void addRunPairs(const Topology& t, const LevelBuild& L, const std::vector<char>& present, Level& level) {
    // Directed edge -> level triangle.
    std::unordered_map<uint64_t, uint32_t> edgeTri;
    for (uint32_t i = 0; i < level.triangles.size(); ++i)
        for (int k = 0; k < 3; ++k)
            edgeTri.emplace(directedEdgeKey(level.triangles[i][size_t(k)], level.triangles[i][size_t((k + 1) % 3)]), i);
    const Runs& R = L.runs;
    for (uint32_t v = 0; v < t.nv; ++v) {
        uint32_t ri = R.runOf[v];
        if (ri == kNone || R.kept[v] || present[v]) continue;
        const auto& rv = R.runs[ri].vertices;
        size_t pos = R.posInRun[v];
        size_t a = pos, b = pos;
        while (a > 0 && !R.kept[rv[a]]) --a;
        while (b + 1 < rv.size() && !R.kept[rv[b]]) ++b;
        uint32_t va = rv[a], vb = rv[b];
        double s = 0;
        double d = pointSegmentDistance(t.P(v), t.P(va), t.P(vb), &s);
        SimplificationPair p;
        p.vertex = v;
        p.coarse = {va, vb, vb};
        p.bary = {float(1 - s), float(s), 0.f};
        auto it = edgeTri.find(directedEdgeKey(va, vb));
        if (it == edgeTri.end()) it = edgeTri.find(directedEdgeKey(vb, va));
        p.face = it != edgeTri.end() ? level.faces[it->second] : L.regions.rep[R.runs[ri].regionA];
        p.deviation = float(d);
        level.pairs.push_back(p);
    }
}

}  // namespace

Level assembleLevel(const Topology& t, const LevelBuild& L) {
    const Regions& r = L.regions;
    Level level;
    level.faceRegion.resize(t.nf);
    for (uint32_t f = 0; f < t.nf; ++f) level.faceRegion[f] = r.rep[r.of[f]];
    level.regionCount = r.count();
    std::vector<uint32_t> triRegion;
    addTriangles(t, L, level, triRegion);
    std::vector<char> present(t.nv, 0);
    for (const Tri& tr : level.triangles)
        for (uint32_t v : tr) present[v] = 1;
    addInteriorPairs(t, L, present, triRegion, level);
    addRunPairs(t, L, present, level);
    std::sort(level.pairs.begin(), level.pairs.end(),
              [](const SimplificationPair& x, const SimplificationPair& y) { return x.vertex < y.vertex; });
    double sum = 0, maxDev = 0;
    for (const auto& p : level.pairs) sum += p.deviation, maxDev = std::max(maxDev, double(p.deviation));
    level.maxDeviation = maxDev;
    level.meanDeviation = level.pairs.empty() ? 0 : sum / double(level.pairs.size());
    return level;
}

}  // namespace lodbake::agsphere_detail

// A level's mesh (level_mesh.h): one indexed primitive, back faces, rounded sliver corners.
#include "lod/level_mesh.h"

#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <tuple>
#include <unordered_map>

#include "lodbake/core/math.h"

namespace lodbake::lod_detail {
namespace {

// Twice the signed UV area in the glTF convention (v down): > 0 for a front-facing triangle. In
// the point type's own precision: on the float UVs the file stores, the differences round as
// float, the rounding that can fold a sliver and that this test looks for (core's signedArea,
// math.h, works in double).
template <class P>
double uvArea2(const P& a, const P& b, const P& c) {
    return double(b.x - a.x) * double(a.y - c.y) - double(a.y - b.y) * double(c.x - a.x);
}

// Appends a copy of vertex v's joints, weights and morph deltas (a vertex being duplicated);
// `flipNormal` negates the normal deltas of a back-face copy.
void copyInfluences(LodLevelData& out, uint32_t v, bool flipNormal = false) {
    for (auto* targets : {&out.targetPositions, &out.targetNormals, &out.targetTangents})
        for (std::vector<float>& d : *targets) {
            if (d.empty()) continue;
            const double sign = flipNormal && targets == &out.targetNormals ? -1 : 1;
            for (size_t k = 0; k < 3; ++k) d.push_back(float(sign * d[3 * v + k]));
        }
    if (out.joints.empty()) return;
    for (size_t d = 0; d < 4; ++d) out.joints.push_back(out.joints[4 * v + d]);
    for (size_t d = 0; d < 4; ++d) out.weights.push_back(out.weights[4 * v + d]);
}

// A sliver whose page UVs face the right way in double precision may turn flat or flipped once
// they are rounded to float. The level mesh is indexed (a vertex is shared by the triangles
// around it), so the sliver gets its own copy of the corner opposite its longest edge, moved one
// float ulp at a time along the gradient of its area (at most 64 ulps, far below a texel) until
// the rounded triangle faces the right way. parameterize has its own repair for per-face-corner
// UVs that are rounded later (nudgeRoundedSliverCorners); this one works on the float buffers.
void splitRoundedSliverCorners(const std::vector<std::array<Vec2, 3>>& placed, LodLevelData& out) {
    struct F2 { float x, y; };
    for (size_t t = 0; t < placed.size(); ++t) {
        const auto& e = placed[t];
        if (!(uvArea2(e[0], e[1], e[2]) > 0)) continue;  // folded for real: not a rounding artefact
        uint32_t* idx = &out.indices[3 * t];
        auto uvOf = [&](uint32_t v) { return F2{out.uvs[2 * v], out.uvs[2 * v + 1]}; };
        if (uvArea2(uvOf(idx[0]), uvOf(idx[1]), uvOf(idx[2])) > 0) continue;
        const size_t k = cornerOppositeLongestEdge(e);
        // The area is invariant under cyclic turns: with c the moved corner, a and b the others,
        // dA/dc = (-(a.y - b.y), -(b.x - a.x)).
        F2 a = uvOf(idx[(k + 1) % 3]), b = uvOf(idx[(k + 2) % 3]), c = uvOf(idx[k]);
        const float gx = -(a.y - b.y), gy = -(b.x - a.x);
        for (int step = 0; step < 64 && !(uvArea2(a, b, c) > 0); ++step) {
            if (gx != 0) c.x = std::nextafter(c.x, gx > 0 ? 2.f : -2.f);
            if (gy != 0) c.y = std::nextafter(c.y, gy > 0 ? 2.f : -2.f);
        }
        uint32_t v = idx[k], copy = uint32_t(out.uvs.size() / 2);
        for (int d = 0; d < 3; ++d) out.positions.push_back(out.positions[3 * v + uint32_t(d)]);
        for (int d = 0; d < 3; ++d) out.normals.push_back(out.normals[3 * v + uint32_t(d)]);
        copyInfluences(out, v);
        out.uvs.insert(out.uvs.end(), {c.x, c.y});
        idx[k] = copy;
    }
}

// What a level vertex is welded by: vertex, chart, normal, chart UV (a level's own charts may give
// a vertex two UVs in one chart), influences. Keys are equal by value (+0 and -0 alike); the
// vertices are numbered in the order their first corner comes, whatever the table's order.
using CornerKey = std::tuple<uint32_t, uint32_t, float, float, float, double, double, uint32_t>;

struct CornerKeyHash {
    size_t operator()(const CornerKey& k) const {
        uint64_t h = 0;
        auto mix = [&h](uint64_t x) { h = (h ^ x) * 0x9E3779B97F4A7C15ull + (h >> 29); };
        auto bitsOf = [](auto x) {  // + 0 turns -0 into +0
            x += decltype(x)(0);
            uint64_t b = 0;
            std::memcpy(&b, &x, sizeof x);
            return b;
        };
        mix(std::get<0>(k));
        mix(std::get<1>(k));
        mix(bitsOf(std::get<2>(k)));
        mix(bitsOf(std::get<3>(k)));
        mix(bitsOf(std::get<4>(k)));
        mix(bitsOf(std::get<5>(k)));
        mix(bitsOf(std::get<6>(k)));
        mix(std::get<7>(k));
        return size_t(h ^ (h >> 32));
    }
};

}  // namespace

bool sameLevelMesh(const LodLevelData& a, const LodLevelData& b) {
    return a.positions == b.positions && a.normals == b.normals && a.uvs == b.uvs && a.tangents == b.tangents && a.joints == b.joints &&
           a.weights == b.weights && a.targetPositions == b.targetPositions && a.targetNormals == b.targetNormals &&
           a.targetTangents == b.targetTangents && a.indices == b.indices;
}

std::vector<size_t> addBackFaces(const Asset& asset, const LevelView& lv, LodLevelData& out) {
    std::vector<size_t> source;
    const TriMesh& m = asset.mesh;
    std::unordered_map<uint32_t, uint32_t> back;  // vertex -> its back-facing copy
    auto copyOf = [&](uint32_t v) {
        auto [it, inserted] = back.emplace(v, uint32_t(out.positions.size() / 3));
        if (inserted) {
            for (size_t d = 0; d < 3; ++d) out.positions.push_back(out.positions[3 * v + d]);
            for (size_t d = 0; d < 3; ++d) out.normals.push_back(-out.normals[3 * v + d]);
            for (size_t d = 0; d < 2; ++d) out.uvs.push_back(out.uvs[2 * v + d]);
            copyInfluences(out, v, true);
        }
        return it->second;
    };
    const size_t triangles = out.indices.size() / 3;
    for (size_t t = 0; t < triangles; ++t) {
        const int32_t mi = m.triangleMaterial.empty() ? -1 : m.triangleMaterial[lv.faces[t]];
        if (mi < 0 || size_t(mi) >= asset.materials.size() || !asset.materials[size_t(mi)].doubleSided) continue;
        const uint32_t a = copyOf(out.indices[3 * t]), b = copyOf(out.indices[3 * t + 1]), c = copyOf(out.indices[3 * t + 2]);
        out.indices.insert(out.indices.end(), {a, c, b});
        source.push_back(t);
    }
    return source;
}

void buildLevelMesh(const Asset& asset, const LevelView& lv, const LevelUVs& luv, const LevelAtlas& la, LodLevelData& out) {
    std::vector<std::array<Vec2, 3>> placed(lv.triangles.size());
    const TriMesh& m = asset.mesh;
    const std::vector<Vec3>& positions = lv.positionsOr(m);
    const AtlasResult& a = la.atlas;
    // Normals: the wedges' (unit) when the asset has them, else area-weighted over this level.
    std::vector<Vec3> vertexNormal;
    bool wedgeNormals = !m.wedges.normal.empty();
    if (!wedgeNormals) {
        vertexNormal.assign(m.vertexCount(), Vec3{});
        for (const Tri& t : lv.triangles) {
            Vec3 n = cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
            for (uint32_t v : t) vertexNormal[v] += n;
        }
    }
    // Welded vertices whose wedges move differently (other influences, other morph deltas) stay
    // apart: the key holds the id of the wedge's influence set and deltas (0 when static).
    const bool skinned = !asset.rig.empty() && m.wedges.joints.size() == m.wedges.size();
    const std::vector<MorphDeltas>& targets = m.wedges.targets;
    const bool morphed = !asset.morph.empty() && targets.size() == asset.morph.size();
    if (morphed) {
        out.targetPositions.assign(targets.size(), {});
        out.targetNormals.assign(targets.size(), {});
    }
    std::map<std::vector<double>, uint32_t> motionIds;
    std::vector<double> motion;
    auto motionOf = [&](uint32_t w) -> uint32_t {
        if (!skinned && !morphed) return 0;
        motion.clear();
        if (skinned) {
            const Vec4& q = m.wedges.weights[w];
            for (uint16_t j : m.wedges.joints[w]) motion.push_back(j);
            motion.insert(motion.end(), {q.x, q.y, q.z, q.w});
        }
        if (morphed)
            for (const MorphDeltas& D : targets) {
                for (const std::vector<Vec3>* d : {&D.position, &D.normal, &D.tangent})
                    if (!d->empty()) motion.insert(motion.end(), {(*d)[w].x, (*d)[w].y, (*d)[w].z});
            }
        return motionIds.emplace(motion, uint32_t(motionIds.size())).first->second;
    };
    auto pushDeltas = [&](const std::vector<Vec3>& d, std::vector<float>& to, uint32_t w) {
        if (!d.empty()) to.insert(to.end(), {float(d[w].x), float(d[w].y), float(d[w].z)});
    };
    std::unordered_map<CornerKey, uint32_t, CornerKeyHash> index;
    index.reserve(lv.triangles.size());
    for (size_t t = 0; t < lv.triangles.size(); ++t) {
        uint32_t c = luv.chart[t];
        const ChartPlacement& P = a.charts[size_t(la.chartSlot[c])];
        for (size_t j = 0; j < 3; ++j) {
            uint32_t v = lv.triangles[t][j];
            Vec3 n = wedgeNormals ? m.wedges.normal[lv.cornerWedges[t][j]] : vertexNormal[v];
            n = normalize(n);
            if (!(length(n) > 0.5)) {
                Vec3 fn = normalize(cross(positions[lv.triangles[t][1]] - positions[lv.triangles[t][0]],
                                          positions[lv.triangles[t][2]] - positions[lv.triangles[t][0]]));
                n = length(fn) > 0.5 ? fn : Vec3{0, 0, 1};
            }
            const uint32_t w = lv.cornerWedges[t][j];
            CornerKey key{v, c, float(n.x), float(n.y), float(n.z), luv.uv[t][j].x, luv.uv[t][j].y, motionOf(w)};
            auto [it, inserted] = index.try_emplace(key, uint32_t(out.positions.size() / 3));
            if (inserted) {
                const Vec3& p = positions[v];
                out.positions.insert(out.positions.end(), {float(p.x), float(p.y), float(p.z)});
                out.normals.insert(out.normals.end(), {float(n.x), float(n.y), float(n.z)});
                Vec2 q = P.apply(luv.uv[t][j]);
                out.uvs.insert(out.uvs.end(), {float(q.x / a.width), float(q.y / a.height)});
                if (skinned) {
                    const Vec4& wt = m.wedges.weights[w];
                    for (uint16_t jo : m.wedges.joints[w]) out.joints.push_back(jo);
                    out.weights.insert(out.weights.end(), {float(wt.x), float(wt.y), float(wt.z), float(wt.w)});
                }
                if (morphed) {
                    // Normal deltas only over wedge normals (a level of area-weighted normals has
                    // none); no tangent deltas: the level's tangents are recomputed from its atlas.
                    for (size_t t = 0; t < targets.size(); ++t) {
                        pushDeltas(targets[t].position, out.targetPositions[t], w);
                        if (wedgeNormals) pushDeltas(targets[t].normal, out.targetNormals[t], w);
                    }
                }
            }
            out.indices.push_back(it->second);
            Vec2 q = P.apply(luv.uv[t][j]);
            placed[t][j] = {q.x / a.width, q.y / a.height};
        }
    }
    splitRoundedSliverCorners(placed, out);
}

}  // namespace lodbake::lod_detail

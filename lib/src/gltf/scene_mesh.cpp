// The welded mesh of a glTF scene (scene_mesh.h): primitives into one TriMesh, welded by position.
#include "gltf/scene_mesh.h"

#include <algorithm>
#include <string>

#include <tiny_gltf.h>

#include "gltf/variants_codec.h"
#include "lodbake/core/weld.h"

namespace lodbake::gltf_detail {
namespace {

struct MeshBuilder {
    TriMesh mesh;
    PositionWeld weld;
    // Wedge attributes are stored once a primitive has them (earlier wedges get the defaults).
    bool hasNormal = false, hasTangent = false, hasUv0 = false, hasUv1 = false, hasColor = false;
    std::vector<std::array<uint16_t, 4>> joints;  // influences of the primitive being added (skinned assets)
    std::vector<Vec4> weights;
    size_t degenerate = 0;

    void add(const ReadContext& c, const PrimData& p, const Mat4& world, int material, const std::string& what, RigRead& rr,
             const NodeInfluence* binding, const MorphLayout& layout, int node) {
        const double det = det3(world);
        const NodeFrame frame = nodeFrame(world);
        const double sgn = frame.sign;
        const std::array<double, 9>& C = frame.cofactor;
        if (mesh.wedges.targets.size() != layout.size()) mesh.wedges.targets.resize(layout.size());
        std::vector<Vec3> wp(p.pos.size());
        std::vector<PositionKey> keys(p.pos.size());
        for (size_t i = 0; i < wp.size(); ++i) {
            wp[i] = transformPoint(world, p.pos[i]);
            if (!isFinite(wp[i])) fail(c, what + ": vertex " + std::to_string(i) + " has a non-finite world position");
            keys[i] = positionKey(wp[i]);
        }
        Wedges& W = mesh.wedges;
        const size_t wedges = W.vertex.size();
        auto start = [&](bool& has, bool present, auto& column, auto fill) {
            if (present && !has) column.assign(wedges, fill);
            has |= present;
        };
        start(hasNormal, !p.normal.empty(), W.normal, Vec3{0, 0, 0});
        start(hasTangent, !p.tangent.empty(), W.tangent, Vec4{1, 0, 0, 1});
        start(hasUv0, !p.uv0.empty(), W.uv0, Vec2{0, 0});
        start(hasUv1, !p.uv1.empty(), W.uv1, Vec2{0, 0});
        start(hasColor, !p.color.empty(), W.color, Vec4{1, 1, 1, 1});
        joints.clear();
        weights.clear();
        if (binding) primitiveInfluences(c, p, *binding, rr, joints, weights, what);
        std::vector<int64_t> local(p.pos.size(), -1);
        // Room for this primitive up front (geometric growth: many small primitives stay linear).
        auto grow = [](auto& v, size_t more) {
            if (v.capacity() < v.size() + more) v.reserve(std::max(v.size() + more, 2 * v.capacity()));
        };
        size_t nv = p.pos.size(), nt = p.tris.size();
        weld.reserve(nv);
        grow(mesh.positions, nv);
        grow(W.vertex, nv);
        if (hasNormal) grow(W.normal, nv);
        if (hasTangent) grow(W.tangent, nv);
        if (hasUv0) grow(W.uv0, nv);
        if (hasUv1) grow(W.uv1, nv);
        if (hasColor) grow(W.color, nv);
        if (binding) {
            grow(W.joints, nv);
            grow(W.weights, nv);
        }
        grow(mesh.cornerWedges, nt);
        grow(mesh.triangles, nt);
        grow(mesh.triangleMaterial, nt);
        auto wedgeOf = [&](uint32_t i) -> uint32_t {
            if (local[i] >= 0) return uint32_t(local[i]);
            bool inserted = false;
            uint32_t v = weld.insert(keys[i], inserted);
            if (inserted) mesh.positions.push_back(Vec3{wp[i].x + 0.0, wp[i].y + 0.0, wp[i].z + 0.0});
            uint32_t w = uint32_t(W.vertex.size());
            W.vertex.push_back(v);
            if (hasNormal) {
                Vec3 n{0, 0, 0};
                if (!p.normal.empty()) {
                    Vec3 a = p.normal[i];
                    n = normalize(Vec3{C[0] * a.x + C[1] * a.y + C[2] * a.z, C[3] * a.x + C[4] * a.y + C[5] * a.z,
                                       C[6] * a.x + C[7] * a.y + C[8] * a.z}) * sgn;
                    if (!isFinite(n)) n = {0, 0, 0};
                }
                W.normal.push_back(n);
            }
            if (hasTangent) {
                Vec4 t{1, 0, 0, 1};
                if (!p.tangent.empty()) {
                    Vec3 d = normalize(transformVector(world, Vec3{p.tangent[i].x, p.tangent[i].y, p.tangent[i].z}));
                    t = {d.x, d.y, d.z, (p.tangent[i].w < 0 ? -1.0 : 1.0) * sgn};
                }
                W.tangent.push_back(t);
            }
            if (hasUv0) W.uv0.push_back(p.uv0.empty() ? Vec2{0, 0} : p.uv0[i]);
            if (hasUv1) W.uv1.push_back(p.uv1.empty() ? Vec2{0, 0} : p.uv1[i]);
            if (hasColor) W.color.push_back(p.color.empty() ? Vec4{1, 1, 1, 1} : p.color[i]);
            if (binding) {
                W.joints.push_back(joints[i]);
                W.weights.push_back(weights[i]);
            }
            if (!W.targets.empty()) appendWedgeDeltas(layout, node, p, i, frame, W);
            local[i] = w;
            return w;
        };
        // The weld's slots of the corners a few triangles ahead are fetched while these are added
        // (the table is not rehashed within the primitive: reserved above).
        constexpr size_t kAhead = 8;
        for (size_t j = 0; j < nt; ++j) {
            if (j + kAhead < nt)
                for (uint32_t i : p.tris[j + kAhead])
                    if (local[i] < 0) weld.prefetch(keys[i]);
            Tri t = p.tris[j];
            if (det < 0) std::swap(t[1], t[2]);
            if (keys[t[0]] == keys[t[1]] || keys[t[1]] == keys[t[2]] || keys[t[0]] == keys[t[2]]) {
                degenerate++;
                continue;
            }
            Tri cw{wedgeOf(t[0]), wedgeOf(t[1]), wedgeOf(t[2])};
            mesh.cornerWedges.push_back(cw);
            mesh.triangles.push_back({W.vertex[cw[0]], W.vertex[cw[1]], W.vertex[cw[2]]});
            mesh.triangleMaterial.push_back(material);
        }
    }

    void finish(Asset& asset) {
        if (degenerate) asset.warnings.push_back(std::to_string(degenerate) + " degenerate triangles dropped");
        asset.mesh = std::move(mesh);
    }
};

}  // namespace

void weldScene(const ReadContext& c, const std::vector<std::pair<int, Mat4>>& nodes, RigRead& rr, const MorphLayout& layout,
               Asset& asset) {
    const tinygltf::Model& model = *c.model;
    MeshBuilder builder;
    for (const auto& [n, world] : nodes) {
        const auto& node = model.nodes[size_t(n)];
        if (node.mesh < 0) continue;
        if (size_t(node.mesh) >= model.meshes.size()) fail(c, "node " + std::to_string(n) + ": mesh " + std::to_string(node.mesh) + " does not exist");
        const auto& mesh = model.meshes[size_t(node.mesh)];
        const auto binding = rr.meshNodes.find(n);
        for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
            PrimData p;
            if (!decodePrimitive(c, node.mesh, int(pi), asset, p)) continue;
            asset.stats.primitives++;
            asset.stats.inputVertices += p.pos.size();
            int material = mesh.primitives[pi].material;
            if (material >= int(model.materials.size())) fail(c, "mesh " + std::to_string(node.mesh) + " primitive " + std::to_string(pi) + ": material " + std::to_string(material) + " does not exist");
            const size_t first = builder.mesh.triangles.size();  // this primitive's triangles, for its variant mapping
            builder.add(c, p, world, material < 0 ? -1 : material,
                        "node " + std::to_string(n) + " mesh " + std::to_string(node.mesh) + " primitive " + std::to_string(pi), rr,
                        binding == rr.meshNodes.end() ? nullptr : &binding->second, layout, n);
            if (!asset.variants.empty())
                assignTriangleMapping(asset.variants, first, builder.mesh.triangles.size(), readPrimitiveMapping(c, node.mesh, int(pi), asset.variants));
        }
    }
    builder.finish(asset);
    if (!asset.variants.empty()) asset.variants.triangleMapping.resize(asset.mesh.triangleCount(), -1);
}

}  // namespace lodbake::gltf_detail

// The LODBAKE_multires extension (docs/LODBAKE_multires.md), both directions: the writer stores
// the original mesh's maps (wedges and faces of every primitive), the levels, collapses, region
// updates, chart layout and texture hierarchy as accessors of the file's own buffer; the reader
// rebuilds the original TriMesh exactly from those maps and checks every index it reads back.
#include "gltf/multires_codec.h"

#include <algorithm>
#include <string>
#include <type_traits>

#include <tiny_gltf.h>

#include "gltf/gltf_internal.h"
#include "gltf/morph_read.h"
#include "gltf/variants_codec.h"
#include "lodbake/core/errors.h"

namespace lodbake::gltf_detail {

using json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Reading

namespace {

// Rebuilds the original TriMesh exactly from mesh `meshIndex` and the extension's maps.
TriMesh rebuildOriginal(const ReadContext& c, const json& ext, const json& orig, int nodeIndex, int meshIndex, const Mat4& world,
                        RigRead& rr, const NodeInfluence* binding, const MorphLayout& layout, Asset& asset) {
    std::string what = std::string(kMultiresExtension) + ": original";
    TriMesh mesh;
    // The counts size the arrays below, so they are checked against the accessors before use: every
    // vertex of the welded original has at least one wedge, every face three faceVertices entries.
    auto count = [&](const char* key) {
        if (!orig.contains(key)) return size_t(0);
        if (!orig[key].is_number_unsigned()) fail(c, what + ": " + key + " is not a non-negative integer");
        return orig[key].get<size_t>();
    };
    size_t V = count("vertexCount"), F = count("faceCount");
    std::vector<uint32_t> wedgeVertex = readU32(c, jint(orig, "wedgeVertex"), 1, what + " wedgeVertex");
    std::vector<uint32_t> faceVertices = readU32(c, jint(orig, "faceVertices"), 3, what + " faceVertices");
    size_t W = wedgeVertex.size();
    if (faceVertices.size() % 3 != 0 || faceVertices.size() / 3 != F) fail(c, what + ": faceVertices count differs from faceCount");
    if (V > W) fail(c, what + ": vertexCount " + std::to_string(V) + " exceeds the " + std::to_string(W) + " wedges");
    for (uint32_t v : wedgeVertex) if (v >= V) fail(c, what + ": wedgeVertex entry out of range");
    for (uint32_t v : faceVertices) if (v >= V) fail(c, what + ": faceVertices entry out of range");
    mesh.positions.assign(V, Vec3{});
    mesh.triangles.resize(F);
    mesh.cornerWedges.assign(F, Tri{0, 0, 0});
    mesh.triangleMaterial.assign(F, -1);
    mesh.wedges.vertex = wedgeVertex;
    std::vector<char> faceSeen(F, 0);
    for (size_t f = 0; f < F; ++f) mesh.triangles[f] = {faceVertices[3 * f], faceVertices[3 * f + 1], faceVertices[3 * f + 2]};
    const json& prims = orig.contains("primitives") ? orig["primitives"] : json::array();
    size_t nPrims = meshIndex >= 0 ? c.model->meshes[size_t(meshIndex)].primitives.size() : 0;
    if (!prims.is_array() || prims.size() != nPrims) fail(c, what + ": primitive maps do not match mesh " + std::to_string(meshIndex));
    bool hasN = false, hasT = false, hasU0 = false, hasU1 = false, hasC = false;
    Wedges& Wd = mesh.wedges;
    Wd.normal.assign(W, Vec3{}); Wd.tangent.assign(W, Vec4{1, 0, 0, 1}); Wd.uv0.assign(W, Vec2{});
    Wd.uv1.assign(W, Vec2{}); Wd.color.assign(W, Vec4{1, 1, 1, 1});
    std::vector<std::array<uint16_t, 4>> joints;  // a primitive's influences (skinned assets)
    std::vector<Vec4> weights;
    if (binding) {
        Wd.joints.assign(W, std::array<uint16_t, 4>{0, 0, 0, 0});
        Wd.weights.assign(W, Vec4{1, 0, 0, 0});
    }
    Wd.targets.resize(layout.size());
    for (MorphDeltas& D : Wd.targets) D.position.assign(W, Vec3{0, 0, 0});
    const NodeFrame frame = nodeFrame(world);
    auto influencesOf = [&](const PrimData& p) {
        joints.clear();
        weights.clear();
        if (binding) primitiveInfluences(c, p, *binding, rr, joints, weights, what);
    };
    for (size_t pi = 0; pi < nPrims; ++pi) {
        PrimData p;
        if (!decodePrimitive(c, meshIndex, int(pi), asset, p)) fail(c, what + ": primitive " + std::to_string(pi) + " is not a triangle primitive");
        asset.stats.primitives++;
        asset.stats.inputVertices += p.pos.size();
        int material = c.model->meshes[size_t(meshIndex)].primitives[pi].material;
        std::vector<uint32_t> wedges = readU32(c, jint(prims[pi], "wedges"), 1, what + " primitive wedges");
        std::vector<uint32_t> faces = readU32(c, jint(prims[pi], "faces"), 1, what + " primitive faces");
        if (wedges.size() != p.pos.size() || faces.size() != p.tris.size())
            fail(c, what + ": primitive " + std::to_string(pi) + " maps do not match its vertices/triangles");
        hasN |= !p.normal.empty(); hasT |= !p.tangent.empty(); hasU0 |= !p.uv0.empty(); hasU1 |= !p.uv1.empty(); hasC |= !p.color.empty();
        influencesOf(p);
        for (size_t i = 0; i < wedges.size(); ++i) {
            uint32_t w = wedges[i];
            if (w >= W) fail(c, what + ": wedge id out of range");
            if (binding) { Wd.joints[w] = joints[i]; Wd.weights[w] = weights[i]; }
            storeWedgeDeltas(layout, nodeIndex, p, i, frame, Wd, w);
            if (!p.normal.empty()) Wd.normal[w] = p.normal[i];
            if (!p.tangent.empty()) Wd.tangent[w] = p.tangent[i];
            if (!p.uv0.empty()) Wd.uv0[w] = p.uv0[i];
            if (!p.uv1.empty()) Wd.uv1[w] = p.uv1[i];
            if (!p.color.empty()) Wd.color[w] = p.color[i];
        }
        for (size_t t = 0; t < faces.size(); ++t) {
            uint32_t f = faces[t];
            if (f >= F) fail(c, what + ": face id out of range");
            faceSeen[f] = 1;
            for (int k = 0; k < 3; ++k) {
                uint32_t li = p.tris[t][size_t(k)];
                mesh.cornerWedges[f][size_t(k)] = wedges[li];
                mesh.positions[mesh.triangles[f][size_t(k)]] = transformPoint(world, p.pos[li]);
            }
            mesh.triangleMaterial[f] = material;
        }
        if (!asset.variants.empty()) {
            const int32_t mapping = readPrimitiveMapping(c, meshIndex, int(pi), asset.variants);
            asset.variants.triangleMapping.resize(F, -1);
            for (uint32_t f : faces) asset.variants.triangleMapping[f] = mapping;
        }
    }
    for (size_t f = 0; f < F; ++f) if (!faceSeen[f]) fail(c, what + ": face " + std::to_string(f) + " is in no primitive");
    // Wedges used only by levels (parameterize's atlas UVs): attributes from the level primitives.
    std::vector<char> wedgeSeen(W, 0);
    for (const Tri& cw : mesh.cornerWedges) for (uint32_t w : cw) wedgeSeen[w] = 1;
    const json& levelsJ = ext.contains("levels") && ext["levels"].is_array() ? ext["levels"] : json::array();
    for (size_t li = 0; li < levelsJ.size(); ++li) {
        const json& L = levelsJ[li];
        int lm = jint(L, "mesh");
        if (!L.contains("primitives") || lm < 0 || size_t(lm) >= c.model->meshes.size()) continue;
        const json& lp = L["primitives"];
        if (!lp.is_array() || lp.size() != c.model->meshes[size_t(lm)].primitives.size())
            fail(c, what + ": level " + std::to_string(li + 1) + " primitive maps do not match its mesh");
        for (size_t pi = 0; pi < lp.size(); ++pi) {
            std::vector<uint32_t> wedges = readU32(c, jint(lp[pi], "wedges"), 1, what + " level primitive wedges");
            bool needed = false;
            for (uint32_t w : wedges) {
                if (w >= W) fail(c, what + ": level wedge id out of range");
                needed |= !wedgeSeen[w];
            }
            if (!needed) continue;
            PrimData p;
            if (!decodePrimitive(c, lm, int(pi), asset, p) || wedges.size() != p.pos.size())
                fail(c, what + ": level " + std::to_string(li + 1) + " primitive maps do not match its vertices");
            hasN |= !p.normal.empty(); hasT |= !p.tangent.empty(); hasU0 |= !p.uv0.empty(); hasU1 |= !p.uv1.empty(); hasC |= !p.color.empty();
            influencesOf(p);
            for (size_t i = 0; i < wedges.size(); ++i) {
                uint32_t w = wedges[i];
                if (wedgeSeen[w] == 1) continue;
                wedgeSeen[w] = 2;
                if (binding) { Wd.joints[w] = joints[i]; Wd.weights[w] = weights[i]; }
                storeWedgeDeltas(layout, nodeIndex, p, i, frame, Wd, w);  // the level repeats the original's targets
                if (!p.normal.empty()) Wd.normal[w] = p.normal[i];  // level nodes only translate
                if (!p.tangent.empty()) Wd.tangent[w] = p.tangent[i];
                if (!p.uv0.empty()) Wd.uv0[w] = p.uv0[i];
                if (!p.uv1.empty()) Wd.uv1[w] = p.uv1[i];
                if (!p.color.empty()) Wd.color[w] = p.color[i];
            }
        }
    }
    // An attribute no primitive has is absent: its array goes, storage and all (the mesh stays
    // loaded for the whole stage).
    auto release = [](auto& v) { std::decay_t<decltype(v)>().swap(v); };
    if (!hasN) release(Wd.normal);
    if (!hasT) release(Wd.tangent);
    if (!hasU0) release(Wd.uv0);
    if (!hasU1) release(Wd.uv1);
    if (!hasC) release(Wd.color);
    return mesh;
}

// A chart layout (charts, or a textureHierarchy rank), checked against the original mesh.
ChartLayout readLayout(const ReadContext& c, const json& C, const TriMesh& mesh, const std::string& what) {
    const size_t V = mesh.vertexCount(), F = mesh.triangleCount();
    auto checkRange = [&](const std::vector<uint32_t>& v, size_t limit, const std::string& name) {
        for (uint32_t x : v) if (x >= limit) fail(c, what + ": " + name + " entry " + std::to_string(x) + " out of range");
    };
    ChartLayout ch;
    ch.chartCount = uint32_t(std::max(0, jint(C, "count", 0)));
    ch.image = jint(C, "image");
    ch.faceChart = readU32(c, jint(C, "faceChart"), 1, what + " faceChart");
    std::vector<float> uv = readF32(c, jint(C, "cornerUV"), 2, what + " cornerUV");
    if (ch.faceChart.size() != F || uv.size() != 6 * F) fail(c, what + ": accessors do not match the face count");
    checkRange(ch.faceChart, ch.chartCount, "faceChart");
    ch.cornerUV.resize(F);
    for (size_t f = 0; f < F; ++f)
        for (size_t k = 0; k < 3; ++k) ch.cornerUV[f][k] = {uv[6 * f + 2 * k], uv[6 * f + 2 * k + 1]};
    if (C.contains("islandVertices")) {
        std::vector<uint32_t> iv = readU32(c, jint(C, "islandVertices"), 1, what + " islandVertices");
        std::vector<float> iuv = readF32(c, jint(C, "islandUV"), 2, what + " islandUV");
        if (iv.size() % 3 != 0 || iuv.size() != 2 * iv.size()) fail(c, what + ": island accessors do not match");
        checkRange(iv, V, "islandVertices");
        ch.islands.resize(iv.size() / 3);
        for (size_t i = 0; i < ch.islands.size(); ++i)
            for (size_t k = 0; k < 3; ++k) {
                ch.islands[i].vertices[k] = iv[3 * i + k];
                ch.islands[i].uv[k] = {iuv[6 * i + 2 * k], iuv[6 * i + 2 * k + 1]};
            }
    }
    return ch;
}

// Version 1 files: a region's faces were listed one after another with the same (oldRep, newRep),
// so the consecutive repeats within each collapse's range are dropped.
void upgradePerFaceUpdates(Multires& mr) {
    std::vector<RegionUpdate> out;
    for (CollapseRecord& r : mr.collapses) {
        const uint32_t begin = uint32_t(out.size());
        for (uint32_t u = r.regionBegin; u < r.regionEnd; ++u) {
            const RegionUpdate& up = mr.regionUpdates[u];
            if (out.size() == begin || out.back().oldRep != up.oldRep || out.back().newRep != up.newRep) out.push_back(up);
        }
        r.regionBegin = begin;
        r.regionEnd = uint32_t(out.size());
    }
    mr.regionUpdates = std::move(out);
}

}  // namespace

const json* findMultiresExtension(const ReadContext& c) {
    const json* ext = nullptr;
    if (c.root.contains("extensions") && c.root["extensions"].is_object() && c.root["extensions"].contains(kMultiresExtension))
        ext = &c.root["extensions"][kMultiresExtension];
    if (ext && !ext->is_object()) fail(c, std::string(kMultiresExtension) + " is not an object");
    if (ext && ext->value("version", 0) > kMultiresVersion)
        throw Unsupported(c.path + ": " + kMultiresExtension + " version " + std::to_string(ext->value("version", 0)) +
                          " is newer than this reader (" + std::to_string(kMultiresVersion) + ")");
    return ext;
}

bool hasMultiresOriginal(const json& ext) { return ext.contains("original") && ext["original"].is_object(); }

int multiresOriginalNode(const json& ext) {
    return ext.contains("original") ? jint(ext["original"], "node", 0) : 0;
}

TriMesh readMultiresOriginal(const ReadContext& c, const json& ext, const std::vector<std::pair<int, Mat4>>& nodes, RigRead& rr,
                             const MorphLayout& layout, Asset& asset) {
    const tinygltf::Model& model = *c.model;
    const json& orig = ext["original"];
    int nodeIndex = jint(orig, "node", 0);
    if (nodeIndex < 0 || size_t(nodeIndex) >= model.nodes.size()) fail(c, std::string(kMultiresExtension) + ": original node does not exist");
    Mat4 world = identity4();
    for (const auto& [n, w] : nodes) if (n == nodeIndex) world = w;
    int meshIndex = model.nodes[size_t(nodeIndex)].mesh;
    if (meshIndex >= int(model.meshes.size())) fail(c, "node " + std::to_string(nodeIndex) + ": mesh does not exist");
    const auto binding = rr.meshNodes.find(nodeIndex);
    return rebuildOriginal(c, ext, orig, nodeIndex, meshIndex, world, rr, binding == rr.meshNodes.end() ? nullptr : &binding->second,
                           layout, asset);
}

Multires readMultires(const ReadContext& c, const json& ext, const TriMesh& mesh) {
    std::string what = kMultiresExtension;
    Multires mr;
    mr.generator = ext.value("generator", std::string("simplify"));
    size_t V = mesh.vertexCount(), F = mesh.triangleCount(), W = mesh.wedges.size();
    auto checkRange = [&](const std::vector<uint32_t>& v, size_t limit, const std::string& name) {
        for (uint32_t x : v) if (x >= limit) fail(c, what + ": " + name + " entry " + std::to_string(x) + " out of range");
    };
    if (ext.contains("levels")) {
        if (!ext["levels"].is_array()) fail(c, what + ": levels is not an array");
        for (size_t li = 0; li < ext["levels"].size(); ++li) {
            const json& L = ext["levels"][li];
            std::string lw = what + " level " + std::to_string(li + 1);
            Level lv;
            lv.targetRatio = L.value("targetRatio", 0.0);
            lv.targetTriangles = L.value("targetTriangles", uint64_t(0));
            lv.targetError = L.value("targetError", 0.0);
            lv.stopReason = L.value("stopReason", std::string());
            lv.regionCount = L.value("regionCount", uint32_t(0));
            lv.collapseCount = L.value("collapseCount", uint32_t(0));
            lv.maxDeviation = L.value("maxDeviation", 0.0);
            lv.meanDeviation = L.value("meanDeviation", 0.0);
            lv.faces = readU32(c, jint(L, "faces"), 1, lw + " faces");
            std::vector<uint32_t> t = readU32(c, jint(L, "triangles"), 3, lw + " triangles");
            std::vector<uint32_t> cw = readU32(c, jint(L, "cornerWedges"), 3, lw + " cornerWedges");
            lv.faceRegion = readU32(c, jint(L, "faceRegion"), 1, lw + " faceRegion");
            std::vector<uint32_t> tm = readU32(c, jint(L, "triangleMaterial"), 1, lw + " triangleMaterial");
            lv.triangleMaterial.assign(tm.begin(), tm.end());  // uint32 bit patterns back to int32 (-1)
            checkRange(lv.faces, F, "faces");
            checkRange(t, V, "triangles");
            checkRange(cw, W, "cornerWedges");
            checkRange(lv.faceRegion, F, "faceRegion");
            if (t.size() != 3 * lv.faces.size() || cw.size() != t.size()) fail(c, lw + ": faces/triangles/cornerWedges counts differ");
            if (!lv.faceRegion.empty() && lv.faceRegion.size() != F) fail(c, lw + ": faceRegion count differs from face count");
            if (!lv.triangleMaterial.empty() && lv.triangleMaterial.size() != lv.faces.size())
                fail(c, lw + ": triangleMaterial count differs from triangle count");
            lv.triangles.resize(lv.faces.size());
            lv.cornerWedges.resize(lv.faces.size());
            for (size_t i = 0; i < lv.faces.size(); ++i) {
                lv.triangles[i] = {t[3 * i], t[3 * i + 1], t[3 * i + 2]};
                lv.cornerWedges[i] = {cw[3 * i], cw[3 * i + 1], cw[3 * i + 2]};
            }
            if (L.contains("pairs")) {
                const json& P = L["pairs"];
                std::vector<uint32_t> pv = readU32(c, jint(P, "vertex"), 1, lw + " pairs.vertex");
                std::vector<uint32_t> pc = readU32(c, jint(P, "coarse"), 3, lw + " pairs.coarse");
                std::vector<float> pb = readF32(c, jint(P, "bary"), 3, lw + " pairs.bary");
                std::vector<uint32_t> pf = readU32(c, jint(P, "face"), 1, lw + " pairs.face");
                std::vector<float> pd = readF32(c, jint(P, "deviation"), 1, lw + " pairs.deviation");
                size_t n = pv.size();
                if (pc.size() != 3 * n || pb.size() != 3 * n || pf.size() != n || pd.size() != n)
                    fail(c, lw + ": pairs accessors have different counts");
                checkRange(pv, V, "pairs.vertex");
                checkRange(pc, V, "pairs.coarse");
                checkRange(pf, F, "pairs.face");
                lv.pairs.resize(n);
                for (size_t i = 0; i < n; ++i) {
                    SimplificationPair& s = lv.pairs[i];
                    s.vertex = pv[i];
                    s.coarse = {pc[3 * i], pc[3 * i + 1], pc[3 * i + 2]};
                    s.bary = {pb[3 * i], pb[3 * i + 1], pb[3 * i + 2]};
                    s.face = pf[i];
                    s.deviation = pd[i];
                }
            }
            mr.levels.push_back(std::move(lv));
        }
    }
    if (ext.contains("collapses")) {
        const json& C = ext["collapses"];
        std::vector<uint32_t> vk = readU32(c, jint(C, "vertices"), 2, what + " collapses.vertices");
        std::vector<float> dev = readF32(c, jint(C, "deviation"), 1, what + " collapses.deviation");
        std::vector<uint32_t> rg = readU32(c, jint(C, "regions"), 2, what + " collapses.regions");
        size_t n = dev.size();
        if (vk.size() != 2 * n || rg.size() != 2 * n) fail(c, what + ": collapses accessors have different counts");
        checkRange(vk, V, "collapses.vertices");
        mr.collapses.resize(n);
        for (size_t i = 0; i < n; ++i) mr.collapses[i] = {vk[2 * i], vk[2 * i + 1], dev[i], rg[2 * i], rg[2 * i + 1]};
    }
    // Version 1 listed one (face, oldRep, newRep) record per relabelled face; version 2 one
    // (oldRep, newRep) per region.
    const bool perFace = ext.value("version", 1) < 2;
    if (ext.contains("regionUpdates")) {
        const size_t width = perFace ? 3 : 2;
        std::vector<uint32_t> ru = readU32(c, jint(ext, "regionUpdates"), int(width), what + " regionUpdates");
        checkRange(ru, F, "regionUpdates");
        mr.regionUpdates.resize(ru.size() / width);
        for (size_t i = 0; i < mr.regionUpdates.size(); ++i)
            mr.regionUpdates[i] = {ru[width * i + width - 2], ru[width * i + width - 1]};
    }
    for (const CollapseRecord& r : mr.collapses)
        if (r.regionBegin > r.regionEnd || r.regionEnd > mr.regionUpdates.size()) fail(c, what + ": collapse region range out of bounds");
    if (perFace) upgradePerFaceUpdates(mr);
    if (ext.contains("charts")) {
        mr.charts = readLayout(c, ext["charts"], mesh, what + " charts");
        mr.charts.material = jint(ext["charts"], "material");
    }
    if (ext.contains("textureHierarchy")) {
        // Written by texture-refine: rank layouts (same schema as charts) and the textures.
        const json& T = ext["textureHierarchy"];
        const std::string tw = what + " textureHierarchy";
        if (!T.is_object()) fail(c, tw + " is not an object");
        const size_t images = c.model ? c.model->images.size() : 0;
        if (T.contains("ranks")) {
            if (!T["ranks"].is_array()) fail(c, tw + ".ranks is not an array");
            for (const json& R : T["ranks"]) {
                ChartLayout lay = readLayout(c, R, mesh, tw + " rank");
                if (lay.image >= int(images)) fail(c, tw + ": rank image out of range");
                mr.textures.ranks.push_back(std::move(lay));
            }
        }
        if (T.contains("textures")) {
            if (!T["textures"].is_array()) fail(c, tw + ".textures is not an array");
            for (const json& X : T["textures"]) {
                HierarchyTexture h;
                int rank = jint(X, "rank", 0), first = -1, last = -1;
                if (X.contains("levels") && X["levels"].is_array() && X["levels"].size() == 2 &&
                    X["levels"][0].is_number_integer() && X["levels"][1].is_number_integer()) {
                    first = X["levels"][0].get<int>();
                    last = X["levels"][1].get<int>();
                }
                h.image = jint(X, "image");
                h.size = jint(X, "size", 0);
                if (rank < 0 || size_t(rank) > mr.textures.ranks.size()) fail(c, tw + ": texture rank out of range");
                if (first < 0 || last < first || size_t(last) > mr.levels.size()) fail(c, tw + ": texture levels out of range");
                // No image (-1): the texture was recorded without baking (pack reads rank, levels, size).
                if (h.image < -1 || h.image >= int(images) || h.size <= 0) fail(c, tw + ": texture image or size out of range");
                h.rank = uint32_t(rank);
                h.firstLevel = uint32_t(first);
                h.lastLevel = uint32_t(last);
                mr.textures.textures.push_back(h);
            }
        }
        if (!mr.textures.textures.empty() && mr.charts.empty()) fail(c, tw + " without charts");
    }
    return mr;
}


// ---------------------------------------------------------------------------------------------
// Writing

namespace {

std::vector<uint32_t> flatten(const std::vector<Tri>& t) {
    std::vector<uint32_t> out;
    out.reserve(t.size() * 3);
    for (const Tri& x : t) out.insert(out.end(), x.begin(), x.end());
    return out;
}

void setIfValid(json& o, const char* key, int accessor) {
    if (accessor >= 0) o[key] = accessor;
}

// A chart layout (charts, or a textureHierarchy rank): count, image, faceChart, cornerUV and the
// optional level-triangle islands.
json layoutJson(BufferBuilder& w, const ChartLayout& ch) {
    std::vector<float> uv;
    uv.reserve(6 * ch.cornerUV.size());
    for (const auto& corners : ch.cornerUV)
        for (const Vec2& c : corners) { uv.push_back(float(c.x)); uv.push_back(float(c.y)); }
    json out = {{"count", ch.chartCount}, {"image", ch.image}};
    setIfValid(out, "faceChart", w.addU32(ch.faceChart, 1));
    setIfValid(out, "cornerUV", w.addFloat(uv, 2, 0, false));
    if (!ch.islands.empty()) {
        std::vector<uint32_t> iv;
        std::vector<float> iuv;
        for (const LayoutIsland& isl : ch.islands)
            for (size_t k = 0; k < 3; ++k) {
                iv.push_back(isl.vertices[k]);
                iuv.push_back(float(isl.uv[k].x));
                iuv.push_back(float(isl.uv[k].y));
            }
        setIfValid(out, "islandVertices", w.addU32(iv, 1));
        setIfValid(out, "islandUV", w.addFloat(iuv, 2, 0, false));
    }
    return out;
}

}  // namespace

json writeMultires(BufferBuilder& w, const Asset& asset, const Multires& mr, const WrittenMeshes& written,
                   const WriteOptions& options) {
    const std::vector<PrimMap>& originalPrims = written.originalPrims;
    const int originalMesh = written.originalMesh;
    const std::vector<int>& levelMeshes = written.levelMeshes;
    const std::vector<std::vector<PrimMap>>& levelPrims = written.levelPrims;
    const TriMesh& mesh = asset.mesh;
    json ext = {{"version", kMultiresVersion}, {"generator", mr.generator}, {"writer", options.generator}};
    json orig = {{"node", 0}, {"vertexCount", mesh.vertexCount()}, {"faceCount", mesh.triangleCount()},
                 {"wedgeCount", mesh.wedges.size()}};
    if (originalMesh >= 0) orig["mesh"] = originalMesh;
    setIfValid(orig, "wedgeVertex", w.addU32(mesh.wedges.vertex, 1));
    setIfValid(orig, "faceVertices", w.addU32(flatten(mesh.triangles), 3));
    json prims = json::array();
    for (const PrimMap& pm : originalPrims) {
        json p = json::object();
        setIfValid(p, "wedges", w.addU32(pm.wedge, 1));
        setIfValid(p, "faces", w.addU32(pm.faces, 1));
        prims.push_back(p);
    }
    orig["primitives"] = prims;
    ext["original"] = orig;
    json levels = json::array();
    for (size_t i = 0; i < mr.levels.size(); ++i) {
        const Level& L = mr.levels[i];
        json l = {{"node", i + 1}, {"targetRatio", L.targetRatio}, {"targetTriangles", L.targetTriangles},
                  {"targetError", L.targetError}, {"stopReason", L.stopReason}, {"collapseCount", L.collapseCount},
                  {"maxDeviation", L.maxDeviation}, {"meanDeviation", L.meanDeviation}, {"regionCount", L.regionCount},
                  {"triangleCount", L.faces.size()}, {"pairCount", L.pairs.size()}};
        if (levelMeshes[i] >= 0) l["mesh"] = levelMeshes[i];
        // Wedge of each level vertex: levels may use wedges no original face uses (parameterize's
        // chart-split atlas UVs); their attributes are read back from the level's primitives.
        json lprims = json::array();
        for (const PrimMap& pm : levelPrims[i]) {
            json p = json::object();
            setIfValid(p, "wedges", w.addU32(pm.wedge, 1));
            lprims.push_back(p);
        }
        if (!lprims.empty()) l["primitives"] = lprims;
        setIfValid(l, "faces", w.addU32(L.faces, 1));
        setIfValid(l, "triangles", w.addU32(flatten(L.triangles), 3));
        setIfValid(l, "cornerWedges", w.addU32(flatten(L.cornerWedges), 3));
        setIfValid(l, "faceRegion", w.addU32(L.faceRegion, 1));
        if (!L.triangleMaterial.empty()) {  // int32 bit patterns: 4294967295 = -1 (no material)
            std::vector<uint32_t> tm(L.triangleMaterial.begin(), L.triangleMaterial.end());
            setIfValid(l, "triangleMaterial", w.addU32(tm, 1));
        }
        if (!L.pairs.empty()) {
            size_t n = L.pairs.size();
            std::vector<uint32_t> pv(n), pc(3 * n), pf(n);
            std::vector<float> pb(3 * n), pd(n);
            for (size_t k = 0; k < n; ++k) {
                const SimplificationPair& s = L.pairs[k];
                pv[k] = s.vertex;
                pf[k] = s.face;
                pd[k] = s.deviation;
                for (int j = 0; j < 3; ++j) { pc[3 * k + size_t(j)] = s.coarse[size_t(j)]; pb[3 * k + size_t(j)] = s.bary[size_t(j)]; }
            }
            l["pairs"] = {{"vertex", w.addU32(pv, 1)}, {"coarse", w.addU32(pc, 3)}, {"bary", w.addFloat(pb, 3, 0, false)},
                          {"face", w.addU32(pf, 1)}, {"deviation", w.addFloat(pd, 1, 0, false)}};
        }
        levels.push_back(l);
    }
    ext["levels"] = levels;
    if (!mr.collapses.empty()) {
        size_t n = mr.collapses.size();
        std::vector<uint32_t> vk(2 * n), rg(2 * n);
        std::vector<float> dev(n);
        for (size_t k = 0; k < n; ++k) {
            const CollapseRecord& c = mr.collapses[k];
            vk[2 * k] = c.removed; vk[2 * k + 1] = c.kept;
            rg[2 * k] = c.regionBegin; rg[2 * k + 1] = c.regionEnd;
            dev[k] = c.deviation;
        }
        ext["collapses"] = {{"count", n}, {"vertices", w.addU32(vk, 2)}, {"deviation", w.addFloat(dev, 1, 0, false)},
                            {"regions", w.addU32(rg, 2)}};
    }
    if (!mr.regionUpdates.empty()) {
        std::vector<uint32_t> ru;
        ru.reserve(2 * mr.regionUpdates.size());
        for (const RegionUpdate& u : mr.regionUpdates) { ru.push_back(u.oldRep); ru.push_back(u.newRep); }
        ext["regionUpdates"] = w.addU32(ru, 2);
    }
    if (!mr.charts.empty()) {
        json charts = layoutJson(w, mr.charts);
        charts["material"] = mr.charts.material;
        ext["charts"] = charts;
    }
    if (!mr.textures.empty()) {
        // texture-refine's hierarchy: rank layouts (schema of charts) and the textures.
        json ranks = json::array(), textures = json::array();
        for (const ChartLayout& lay : mr.textures.ranks) ranks.push_back(layoutJson(w, lay));
        for (const HierarchyTexture& h : mr.textures.textures) {
            json t = {{"rank", h.rank}, {"levels", {h.firstLevel, h.lastLevel}}};
            if (h.image >= 0) t["image"] = h.image;
            t["size"] = h.size;
            textures.push_back(t);
        }
        ext["textureHierarchy"] = {{"ranks", ranks}, {"textures", textures}};
    }
    return ext;
}

}  // namespace lodbake::gltf_detail

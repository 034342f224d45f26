// KHR_draco_mesh_compression: a primitive's Draco bitstream decoded into glTF-local arrays.
#include "gltf/draco_decode.h"

#include <algorithm>
#include <memory>

#include <draco/compression/decode.h>
#include <tiny_gltf.h>

namespace lodbake::gltf_detail {

using json = nlohmann::json;

void decodeDraco(const ReadContext& c, const json& ext, PrimData& p, const std::string& what) {
    std::string w = what + ": KHR_draco_mesh_compression";
    if (!ext.is_object() || !ext.contains("bufferView") || !ext["bufferView"].is_number_integer())
        fail(c, w + ": missing bufferView");
    size_t length = 0;
    const unsigned char* bytes = viewBytes(c, ext["bufferView"].get<int>(), length, w);
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes), length);
    draco::Decoder decoder;
    auto status = decoder.DecodeMeshFromBuffer(&buffer);
    if (!status.ok()) fail(c, w + ": cannot decode: " + status.status().error_msg_string());
    std::unique_ptr<draco::Mesh> mesh = std::move(status).value();
    size_t nPoints = mesh->num_points();
    auto attr = [&](const char* name, int comps) -> std::vector<float> {
        if (!ext.contains("attributes") || !ext["attributes"].is_object() || !ext["attributes"].contains(name)) return {};
        const json& id = ext["attributes"][name];
        if (!id.is_number_integer()) fail(c, w + ": attribute " + name + " id is not an integer");
        const draco::PointAttribute* a = mesh->GetAttributeByUniqueId(id.get<uint32_t>());
        if (!a) fail(c, w + ": attribute " + name + " (id " + id.dump() + ") not in the Draco data");
        std::vector<float> out(nPoints * size_t(comps), comps == 4 ? 1.0f : 0.0f);
        for (size_t i = 0; i < nPoints; ++i) {
            float tmp[4] = {0, 0, 0, 1};
            int nc = std::min<int>(comps, a->num_components());
            if (!a->ConvertValue<float>(a->mapped_index(draco::PointIndex(uint32_t(i))), int8_t(nc), tmp))
                fail(c, w + ": cannot convert attribute " + name);
            for (int k = 0; k < nc; ++k) out[i * size_t(comps) + size_t(k)] = tmp[k];
        }
        if (comps == 4 && std::string(name) == "COLOR_0") {
            // num_components 3 → alpha 1 stays from the fill value
        }
        return out;
    };
    std::vector<float> P = attr("POSITION", 3);
    if (P.empty()) fail(c, w + ": no POSITION attribute");
    p.pos.resize(nPoints);
    for (size_t i = 0; i < nPoints; ++i) p.pos[i] = {P[3 * i], P[3 * i + 1], P[3 * i + 2]};
    std::vector<float> N = attr("NORMAL", 3);
    if (!N.empty()) { p.normal.resize(nPoints); for (size_t i = 0; i < nPoints; ++i) p.normal[i] = {N[3 * i], N[3 * i + 1], N[3 * i + 2]}; }
    std::vector<float> T = attr("TANGENT", 4);
    if (!T.empty()) { p.tangent.resize(nPoints); for (size_t i = 0; i < nPoints; ++i) p.tangent[i] = {T[4 * i], T[4 * i + 1], T[4 * i + 2], T[4 * i + 3]}; }
    std::vector<float> U0 = attr("TEXCOORD_0", 2);
    if (!U0.empty()) { p.uv0.resize(nPoints); for (size_t i = 0; i < nPoints; ++i) p.uv0[i] = {U0[2 * i], U0[2 * i + 1]}; }
    std::vector<float> U1 = attr("TEXCOORD_1", 2);
    if (!U1.empty()) { p.uv1.resize(nPoints); for (size_t i = 0; i < nPoints; ++i) p.uv1[i] = {U1[2 * i], U1[2 * i + 1]}; }
    std::vector<float> C = attr("COLOR_0", 4);
    if (!C.empty()) { p.color.resize(nPoints); for (size_t i = 0; i < nPoints; ++i) p.color[i] = {C[4 * i], C[4 * i + 1], C[4 * i + 2], C[4 * i + 3]}; }
    // Skin influences travel as generic attributes (JOINTS_0 / WEIGHTS_0 named in the extension).
    std::vector<float> J = attr("JOINTS_0", 4), Wt = attr("WEIGHTS_0", 4);
    if (!J.empty() && !Wt.empty()) {
        p.influenceSets = 1;
        p.joints.resize(J.size());
        for (size_t i = 0; i < J.size(); ++i) {
            if (!(J[i] >= 0 && J[i] < 65536)) fail(c, w + ": JOINTS_0 value out of range");
            p.joints[i] = uint32_t(J[i]);
        }
        p.weights.assign(Wt.begin(), Wt.end());
    }
    std::vector<uint32_t> idx;
    idx.reserve(size_t(mesh->num_faces()) * 3);
    for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
        const auto& face = mesh->face(f);
        for (int k = 0; k < 3; ++k) idx.push_back(face[k].value());
    }
    assembleTriangles(c, idx, TINYGLTF_MODE_TRIANGLES, p, w);
    checkFinitePositions(c, p, w);
}

}  // namespace lodbake::gltf_detail

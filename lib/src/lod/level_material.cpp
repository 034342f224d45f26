// A chain level's material from its page bake (see level_material.h).
#include "lod/level_material.h"

#include <algorithm>

#include "lodbake/core/parallel.h"
#include "lodbake/core/tangents.h"
#include "lodbake/texture/ktx2.h"

namespace lodbake::lod_detail {

BakeChannels levelChannels(const MaterialPlan& plan, bool normalMap) {
    BakeChannels c;
    c.alpha = plan.alphaTexture;
    c.orm = plan.ormTexture();
    c.emissive = plan.emissiveTexture;
    c.normal = normalMap && !plan.unlit;
    return c;
}

std::vector<float> levelTangents(const LodLevelData& L) {
    const size_t n = L.positions.size() / 3;
    std::vector<Vec3> p(n), nrm(n);
    std::vector<Vec2> uv(n);
    for (size_t i = 0; i < n; ++i) {
        p[i] = {L.positions[3 * i], L.positions[3 * i + 1], L.positions[3 * i + 2]};
        nrm[i] = {L.normals[3 * i], L.normals[3 * i + 1], L.normals[3 * i + 2]};
        uv[i] = {L.uvs[2 * i], L.uvs[2 * i + 1]};
    }
    std::vector<Tri> tris(L.indices.size() / 3);
    for (size_t t = 0; t < tris.size(); ++t) tris[t] = {L.indices[3 * t], L.indices[3 * t + 1], L.indices[3 * t + 2]};
    const std::vector<Vec4> tan = computeTangents(p, nrm, uv, tris);
    std::vector<float> out(4 * n);
    for (size_t i = 0; i < n; ++i) {
        out[4 * i] = float(tan[i].x);
        out[4 * i + 1] = float(tan[i].y);
        out[4 * i + 2] = float(tan[i].z);
        out[4 * i + 3] = float(tan[i].w);
    }
    return out;
}

BakeTarget levelBakeTarget(const LodLevelData& L, int width, int height) {
    BakeTarget t;
    const double size = std::max(width, height);
    const size_t tris = L.indices.size() / 3;
    t.uv.resize(tris);
    t.normal.resize(tris);
    t.tangent.resize(tris);
    for (size_t f = 0; f < tris; ++f)
        for (size_t k = 0; k < 3; ++k) {
            const size_t v = L.indices[3 * f + k];
            t.uv[f][k] = {L.uvs[2 * v] * width / size, L.uvs[2 * v + 1] * height / size};
            t.normal[f][k] = {L.normals[3 * v], L.normals[3 * v + 1], L.normals[3 * v + 2]};
            if (!L.tangents.empty())
                t.tangent[f][k] = {L.tangents[4 * v], L.tangents[4 * v + 1], L.tangents[4 * v + 2], L.tangents[4 * v + 3]};
        }
    return t;
}

std::vector<std::string> channelNames(const LodMaterial& m) {
    std::vector<std::string> out;
    if (!m.baseColor.encoded.empty()) out.push_back(m.baseColor.channels == 4 ? "baseColorAlpha" : "baseColor");
    if (m.occlusion) out.push_back("occlusion");
    if (m.metallicRoughness) out.push_back("metallicRoughness");
    if (!m.emissive.encoded.empty()) out.push_back("emissive");
    if (!m.normal.encoded.empty()) out.push_back("normal");
    return out;
}

namespace {

// The level's texture as the chain stores it: `image` itself, or its KTX2 when asked.
Image stored(Image image, const LevelImageOptions& o, Ktx2Codec codec, bool srgb, bool normalMap = false) {
    if (o.ktx2Encoder.empty()) return image;
    Ktx2Options k;
    k.encoder = o.ktx2Encoder;
    k.codec = codec;
    k.srgb = srgb;
    k.normalMap = normalMap;
    return encodeKtx2(image, k);
}

}  // namespace

LodMaterial levelMaterial(const MaterialPlan& plan, const BakeResult& baked, int w, int h, const LevelImageOptions& o,
                          const std::string& name) {
    LodMaterial m;
    const size_t texels = size_t(w) * size_t(h);
    // The images to encode, each on its own (on o.threads threads), then stored in this order.
    struct Encode {
        const std::vector<float>* values;
        EncodeOptions options;
        std::string name;
        Image* image;
        Ktx2Codec codec;
        bool normalMap;
    };
    std::vector<Encode> encodes;
    std::vector<float> rgba;
    if (plan.baseColorTexture) {
        if (!baked.alpha.empty()) {
            rgba.resize(texels * 4);
            for (size_t i = 0; i < texels; ++i) {
                for (size_t c = 0; c < 3; ++c) rgba[i * 4 + c] = baked.pixels[i * 3 + c];
                rgba[i * 4 + 3] = baked.alpha[i];
            }
            encodes.push_back({&rgba, EncodeOptions{ImageFormat::Png, o.jpegQuality, 4, true}, name, &m.baseColor, Ktx2Codec::Etc1s, false});
        } else {
            encodes.push_back({&baked.pixels, EncodeOptions{o.format, o.jpegQuality, 3, true}, name, &m.baseColor, Ktx2Codec::Etc1s, false});
        }
        m.baseColorFactor = {1, 1, 1, plan.alphaTexture ? 1.0 : plan.baseColorFactor.w};
    } else {
        m.baseColorFactor = plan.baseColorFactor;
    }
    m.metallicFactor = plan.metallicFactor;
    m.roughnessFactor = plan.roughnessFactor;
    if (!baked.orm.empty()) {
        encodes.push_back({&baked.orm, EncodeOptions{o.format, o.jpegQuality, 3, false}, name + "_orm", &m.orm, Ktx2Codec::Uastc, false});
        m.occlusion = plan.occlusionTexture;
        m.metallicRoughness = plan.metallicRoughnessTexture;
        if (m.metallicRoughness) m.metallicFactor = m.roughnessFactor = 1;
    }
    if (!baked.emissive.empty()) {
        encodes.push_back(
            {&baked.emissive, EncodeOptions{o.format, o.jpegQuality, 3, true}, name + "_emissive", &m.emissive, Ktx2Codec::Etc1s, false});
        m.emissiveFactor = {1, 1, 1};
        m.emissiveStrength = baked.emissiveScale;
    } else {
        m.emissiveFactor = plan.emissiveFactor;
        const double peak = std::max({m.emissiveFactor.x, m.emissiveFactor.y, m.emissiveFactor.z});
        if (peak > 1) {
            m.emissiveFactor = m.emissiveFactor * (1 / peak);
            m.emissiveStrength = peak;
        }
    }
    if (!baked.normal.empty())
        encodes.push_back(
            {&baked.normal, EncodeOptions{ImageFormat::Png, o.jpegQuality, 3, false}, name + "_normal", &m.normal, Ktx2Codec::Uastc, true});
    parallelFor(encodes.size(), o.threads, [&](size_t i) {
        const Encode& e = encodes[i];
        *e.image = encodeImage(*e.values, w, h, e.options, e.name);
    });
    for (const Encode& e : encodes) *e.image = stored(std::move(*e.image), o, e.codec, e.options.srgb, e.normalMap);
    m.alphaMode = plan.alphaMode;
    m.alphaCutoff = plan.alphaCutoff;
    m.doubleSided = plan.doubleSided;
    m.unlit = plan.unlit;
    return m;
}

}  // namespace lodbake::lod_detail

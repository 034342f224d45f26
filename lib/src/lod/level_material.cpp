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
    const ExtensionPlan& x = plan.ext;
    c.clearcoat = x.clearcoatTexture || x.clearcoatRoughnessTexture;
    // Like the normal map: a coarse level's clearcoat shows the original's finer surface.
    c.clearcoatNormal = x.factors.clearcoat.present && (x.clearcoatNormalTexture || c.normal);
    c.sheen = x.sheenColorTexture || x.sheenRoughnessTexture;
    c.specular = x.specularTexture || x.specularColorTexture;
    c.transmission = x.transmissionTexture || x.thicknessTexture;
    c.iridescence = x.iridescenceTexture || x.iridescenceThicknessTexture;
    c.diffuseTransmission = x.diffuseTransmissionTexture || x.diffuseTransmissionColorTexture;
    c.anisotropy = x.anisotropyTexture;
    c.clearcoatRoughnessFill = x.clearcoatRoughnessFill;
    c.sheenRoughnessFill = x.sheenRoughnessFill;
    c.specularColorScale = x.specularColorScale;
    c.thicknessScale = x.factors.volume.thicknessFactor > 0 ? x.factors.volume.thicknessFactor : 1;
    c.iridescenceThicknessMin = x.factors.iridescence.thicknessMinimum;
    c.iridescenceThicknessMax = x.factors.iridescence.thicknessMaximum;
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
    // Each extension channel with a texture, in MaterialExtensions order.
    const MaterialExtensions& e = m.ext;
    const std::pair<const char*, const TextureRef*> named[] = {
        {"clearcoat", &e.clearcoat.texture},
        {"clearcoatRoughness", &e.clearcoat.roughnessTexture},
        {"clearcoatNormal", &e.clearcoat.normalTexture},
        {"sheenColor", &e.sheen.colorTexture},
        {"sheenRoughness", &e.sheen.roughnessTexture},
        {"transmission", &e.transmission.texture},
        {"thickness", &e.volume.thicknessTexture},
        {"specular", &e.specular.texture},
        {"specularColor", &e.specular.colorTexture},
        {"iridescence", &e.iridescence.texture},
        {"iridescenceThickness", &e.iridescence.thicknessTexture},
        {"anisotropy", &e.anisotropy.texture},
        {"diffuseTransmission", &e.diffuseTransmission.texture},
        {"diffuseTransmissionColor", &e.diffuseTransmission.colorTexture},
    };
    for (const auto& [name, ref] : named)
        if (ref->texture >= 0) out.push_back(name);
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
    // The extensions: the plan's factors, and the baked images with the channels they carry.
    m.ext = plan.ext.factors;
    const ExtensionPlan& x = plan.ext;
    struct ExtensionImage {
        const std::vector<float>* values;
        const char* suffix;
        int channels;
        bool srgb, normalMap;
        std::vector<TextureRef*> refs;  // the references that read it
    };
    MaterialExtensions& e = m.ext;
    auto pick = [](bool textured, TextureRef& ref) { return textured ? &ref : nullptr; };
    const ExtensionImage extension[] = {
        {&baked.clearcoat, "clearcoat", 3, false, false,
         {pick(x.clearcoatTexture, e.clearcoat.texture), pick(x.clearcoatRoughnessTexture, e.clearcoat.roughnessTexture)}},
        {&baked.clearcoatNormal, "clearcoatNormal", 3, false, true, {&e.clearcoat.normalTexture}},
        {&baked.sheen, "sheen", 4, true, false,
         {pick(x.sheenColorTexture, e.sheen.colorTexture), pick(x.sheenRoughnessTexture, e.sheen.roughnessTexture)}},
        {&baked.specular, "specular", 4, true, false,
         {pick(x.specularColorTexture, e.specular.colorTexture), pick(x.specularTexture, e.specular.texture)}},
        {&baked.transmission, "transmission", 3, false, false,
         {pick(x.transmissionTexture, e.transmission.texture), pick(x.thicknessTexture, e.volume.thicknessTexture)}},
        {&baked.iridescence, "iridescence", 3, false, false,
         {pick(x.iridescenceTexture, e.iridescence.texture), pick(x.iridescenceThicknessTexture, e.iridescence.thicknessTexture)}},
        {&baked.diffuseTransmission, "diffuseTransmission", 4, true, false,
         {pick(x.diffuseTransmissionColorTexture, e.diffuseTransmission.colorTexture),
          pick(x.diffuseTransmissionTexture, e.diffuseTransmission.texture)}},
        {&baked.anisotropy, "anisotropy", 3, false, true, {&e.anisotropy.texture}},
    };
    size_t images = 0;
    for (const ExtensionImage& ei : extension) images += ei.values->empty() ? 0 : 1;
    m.extensionImages.resize(images);  // sized once: the encodes point into it
    std::vector<std::string> suffixes;  // the images' names after encoding (which names them after the level)
    size_t next = 0;
    for (const ExtensionImage& ei : extension) {
        if (ei.values->empty()) continue;
        Image& image = m.extensionImages[next];
        suffixes.push_back(ei.suffix);
        for (TextureRef* ref : ei.refs)
            if (ref) *ref = TextureRef{int(next), 0, ref->scale, {}};
        // RGBA and normal maps are PNG (JPEG has no alpha and blurs directions).
        const ImageFormat format = ei.channels == 4 || ei.normalMap ? ImageFormat::Png : o.format;
        encodes.push_back({ei.values, EncodeOptions{format, o.jpegQuality, ei.channels, ei.srgb}, name + "_" + ei.suffix, &image,
                           ei.srgb ? Ktx2Codec::Etc1s : Ktx2Codec::Uastc, ei.normalMap});
        ++next;
    }
    parallelFor(encodes.size(), o.threads, [&](size_t i) {
        const Encode& e = encodes[i];
        *e.image = encodeImage(*e.values, w, h, e.options, e.name);
    });
    for (const Encode& en : encodes) *en.image = stored(std::move(*en.image), o, en.codec, en.options.srgb, en.normalMap);
    for (size_t i = 0; i < m.extensionImages.size(); ++i) m.extensionImages[i].name = suffixes[i];
    m.alphaMode = plan.alphaMode;
    m.alphaCutoff = plan.alphaCutoff;
    m.doubleSided = plan.doubleSided;
    m.unlit = plan.unlit;
    return m;
}

}  // namespace lodbake::lod_detail

// The source-image cache (bake_sources.h): BakeSources marks the images some material channel
// references and computes the missing tangent frames; a bake decodes the images its channels read
// before it shades (decodeSources), and a lookup of an image not decoded yet decodes it there.
#include "bake/bake_sources.h"

#include <algorithm>
#include <initializer_list>
#include <memory>
#include <string>

#include "lodbake/core/errors.h"
#include "lodbake/core/parallel.h"
#include "lodbake/core/tangents.h"
#include "lodbake/texture/codec.h"
#include "lodbake/texture/texture_transform.h"

namespace lodbake {
namespace bake_detail {
namespace {

// The image a texture reference samples; -1 when it names no texture or image of the asset.
int imageOf(const Asset& asset, const TextureRef& ref) {
    if (ref.texture < 0 || ref.texture >= int(asset.textures.size())) return -1;
    const int i = asset.textures[size_t(ref.texture)].image;
    return i >= 0 && i < int(asset.images.size()) ? i : -1;
}

// The extension texture references that baking `ch` reads.
std::vector<const TextureRef*> extensionRefs(const MaterialExtensions& e, const BakeChannels& ch) {
    std::vector<const TextureRef*> refs;
    auto add = [&](bool on, std::initializer_list<const TextureRef*> list) {
        if (on) refs.insert(refs.end(), list);
    };
    add(ch.clearcoat, {&e.clearcoat.texture, &e.clearcoat.roughnessTexture});
    add(ch.clearcoatNormal, {&e.clearcoat.normalTexture});
    add(ch.sheen, {&e.sheen.colorTexture, &e.sheen.roughnessTexture});
    add(ch.specular, {&e.specular.texture, &e.specular.colorTexture});
    add(ch.transmission, {&e.transmission.texture, &e.volume.thicknessTexture});
    add(ch.iridescence, {&e.iridescence.texture, &e.iridescence.thicknessTexture});
    add(ch.diffuseTransmission, {&e.diffuseTransmission.texture, &e.diffuseTransmission.colorTexture});
    add(ch.anisotropy, {&e.anisotropy.texture});
    return refs;
}

}  // namespace

// The decoded MIP levels of image i, decoded by the first caller (others wait for it).
// \throw IOError (the image cannot be decoded).
const MipTexture& decodedSource(const Asset& asset, SourceTexture& src, size_t i) {
    std::call_once(src.decoded, [&] {
        DecodedImage img;
        std::string error;
        if (!decodeImage(asset.images[i], img, error, DecodeDepth::KeepEightBit))
            throw IOError("cannot decode for baking: " + error);
        src.mip = buildMipTexture(img);
    });
    return src.mip;
}

// Decodes, on `threads` threads, every image that baking `ch` reads (each once, in any order:
// each is decoded on its own), so the shading threads do not wait on one another's decodes.
void decodeSources(const Asset& asset, std::vector<SourceTexture>& sources, const BakeChannels& ch, int threads) {
    std::vector<size_t> images;
    for (const Material& m : asset.materials) {
        const TextureRef* refs[] = {&m.baseColor, ch.orm ? &m.metallicRoughness : nullptr, ch.orm ? &m.occlusion : nullptr,
                                    ch.orm ? &m.specularGlossiness : nullptr, ch.emissive ? &m.emissive : nullptr,
                                    ch.normal ? &m.normal : nullptr};
        for (const TextureRef* ref : refs) {
            const int i = ref ? imageOf(asset, *ref) : -1;
            if (i >= 0 && sources[size_t(i)].used) images.push_back(size_t(i));
        }
        for (const TextureRef* ref : extensionRefs(m.ext, ch)) {
            const int i = imageOf(asset, *ref);
            if (i >= 0 && sources[size_t(i)].used) images.push_back(size_t(i));
        }
    }
    std::sort(images.begin(), images.end());
    images.erase(std::unique(images.begin(), images.end()), images.end());
    parallelFor(images.size(), threads, [&](size_t k) { decodedSource(asset, sources[images[k]], images[k]); });
}

}  // namespace bake_detail

using bake_detail::imageOf;
using bake_detail::SourceTexture;

struct BakeSources::Impl {
    const Asset& asset;
    std::vector<SourceTexture> sources;  // per image
    std::array<std::vector<Vec4>, 2> tangents;  // per UV set a normal map uses, when the file has no TANGENT
    explicit Impl(const Asset& a) : asset(a), sources(a.images.size()) {
        for (const Material& m : asset.materials) {
            std::vector<const TextureRef*> refs = textureRefs(m.ext);
            refs.insert(refs.end(), {&m.baseColor, &m.metallicRoughness, &m.occlusion, &m.emissive, &m.normal, &m.specularGlossiness});
            for (const TextureRef* ref : refs) {
                const int i = imageOf(asset, *ref);
                if (i >= 0) sources[size_t(i)].used = true;
            }
        }
        if (asset.mesh.wedges.tangent.empty())
            for (const Material& m : asset.materials)
                for (const TextureRef* map : {&m.normal, &m.ext.clearcoat.normalTexture, &m.ext.anisotropy.texture}) {
                    // Anisotropy needs the frame even without a texture (its rotation is relative to it).
                    if (map->texture < 0 && !(map == &m.ext.anisotropy.texture && m.ext.anisotropy.present)) continue;
                    const int set = (map->transform.texCoord >= 0 ? map->transform.texCoord : map->texCoord) == 1 ? 1 : 0;
                    if (tangents[size_t(set)].empty())
                        tangents[size_t(set)] = computeWedgeTangents(asset.mesh, normalMapUVs(asset.mesh, asset.materials, set));
                }
    }
};

std::vector<SourceTexture>& BakeSourcesAccess::sources(const BakeSources& s) { return s.impl_->sources; }
const std::array<std::vector<Vec4>, 2>& BakeSourcesAccess::tangents(const BakeSources& s) { return s.impl_->tangents; }

BakeSources::BakeSources(const Asset& asset) : impl_(std::make_unique<Impl>(asset)) {}
BakeSources::~BakeSources() = default;
const Asset& BakeSources::asset() const { return impl_->asset; }

}  // namespace lodbake

// The final LOD chain writer (pack's output) and image encoding.
//
// Pipeline of writeLodChain:
//   1. per level: one mesh with one primitive (plain accessors, or a Draco buffer with
//      accessor stubs whose counts are the encoder's), one material, texture and image;
//   2. node 0 (LOD0) with MSFT_lod.ids and extras.MSFT_screencoverage; only node 0 in the scene;
//   3. serialise (.glb container, or .gltf + .bin [+ images]) and rename into place.
// JSON is built with nlohmann::json (sorted keys: byte-identical output for identical input).

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <nlohmann/json.hpp>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "io/gltf_internal.h"
#include "lodbake/core/errors.h"
#include "lodbake/io/gltf.h"
#include "lodbake/io/lod_chain.h"

namespace lodbake {
namespace {

using json = nlohmann::json;
using namespace gltf_detail;

constexpr const char* kDraco = "KHR_draco_mesh_compression";
constexpr const char* kLod = "MSFT_lod";

struct Buffer {
    std::string bin;
    json views = json::array();
    json accessors = json::array();

    int view(const void* data, size_t bytes, int target) {
        while (bin.size() % 4) bin.push_back('\0');
        json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (target) v["target"] = target;
        bin.append(static_cast<const char*>(data), bytes);
        views.push_back(v);
        return int(views.size()) - 1;
    }
    int accessor(json a) {
        accessors.push_back(std::move(a));
        return int(accessors.size()) - 1;
    }
};

const char* typeName(int comps) { return comps == 2 ? "VEC2" : comps == 3 ? "VEC3" : "SCALAR"; }

json floatAccessor(const std::vector<float>& v, int comps, bool minmax) {
    size_t n = v.size() / size_t(comps);
    json a = {{"componentType", kFloat}, {"count", n}, {"type", typeName(comps)}};
    if (minmax && n > 0) {
        std::vector<float> lo(v.begin(), v.begin() + comps), hi = lo;
        for (size_t i = 0; i < n; ++i)
            for (size_t k = 0; k < size_t(comps); ++k) {
                lo[k] = std::min(lo[k], v[i * size_t(comps) + k]);
                hi[k] = std::max(hi[k], v[i * size_t(comps) + k]);
            }
        a["min"] = lo;
        a["max"] = hi;
    }
    return a;
}

void checkLevel(const std::string& path, const LodLevelData& L) {
    size_t n = L.positions.size() / 3;
    bool ok = n > 0 && L.positions.size() == 3 * n && L.normals.size() == 3 * n && L.uvs.size() == 2 * n &&
              !L.indices.empty() && L.indices.size() % 3 == 0 && !L.image.encoded.empty();
    for (uint32_t i : L.indices) ok = ok && i < n;
    if (!ok) throw InvalidInput(path + ": level '" + L.name + "' has inconsistent mesh data or no image");
}

// Plain accessors for one primitive's attributes and indices.
json plainPrimitive(Buffer& b, const LodLevelData& L) {
    size_t n = L.positions.size() / 3;
    json attrs;
    json pa = floatAccessor(L.positions, 3, true);
    pa["bufferView"] = b.view(L.positions.data(), L.positions.size() * 4, kArrayBuffer);
    attrs["POSITION"] = b.accessor(pa);
    json na = floatAccessor(L.normals, 3, false);
    na["bufferView"] = b.view(L.normals.data(), L.normals.size() * 4, kArrayBuffer);
    attrs["NORMAL"] = b.accessor(na);
    json ta = floatAccessor(L.uvs, 2, false);
    ta["bufferView"] = b.view(L.uvs.data(), L.uvs.size() * 4, kArrayBuffer);
    attrs["TEXCOORD_0"] = b.accessor(ta);
    int iv, ct;
    if (n < 65536) {
        std::vector<uint16_t> s(L.indices.begin(), L.indices.end());
        iv = b.view(s.data(), s.size() * 2, kElementArrayBuffer);
        ct = kUnsignedShort;
    } else {
        iv = b.view(L.indices.data(), L.indices.size() * 4, kElementArrayBuffer);
        ct = kUnsignedInt;
    }
    int ia = b.accessor({{"bufferView", iv}, {"componentType", ct}, {"count", L.indices.size()}, {"type", "SCALAR"}});
    return {{"attributes", attrs}, {"indices", ia}, {"mode", 4}};
}

// KHR_draco_mesh_compression: the Draco bitstream in a buffer view, accessors without views whose
// counts are what the decoder will produce (the encoder may split non-manifold vertices).
json dracoPrimitive(Buffer& b, const LodLevelData& L, const LodChainWriteOptions& o, const std::string& path) {
    size_t n = L.positions.size() / 3, f = L.indices.size() / 3;
    draco::Mesh dm;
    dm.set_num_points(uint32_t(n));
    auto add = [&](draco::GeometryAttribute::Type type, const std::vector<float>& v, int comps) {
        draco::GeometryAttribute ga;
        ga.Init(type, nullptr, int8_t(comps), draco::DT_FLOAT32, false, int64_t(sizeof(float)) * comps, 0);
        int id = dm.AddAttribute(ga, true, uint32_t(n));
        draco::PointAttribute* a = dm.attribute(id);
        for (size_t i = 0; i < n; ++i) a->SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), &v[i * size_t(comps)]);
        return a->unique_id();
    };
    uint32_t pid = add(draco::GeometryAttribute::POSITION, L.positions, 3);
    uint32_t nid = add(draco::GeometryAttribute::NORMAL, L.normals, 3);
    uint32_t tid = add(draco::GeometryAttribute::TEX_COORD, L.uvs, 2);
    dm.SetNumFaces(f);
    for (size_t t = 0; t < f; ++t) {
        draco::Mesh::Face face = {draco::PointIndex(L.indices[3 * t]), draco::PointIndex(L.indices[3 * t + 1]),
                                  draco::PointIndex(L.indices[3 * t + 2])};
        dm.SetFace(draco::FaceIndex(uint32_t(t)), face);
    }
    draco::Encoder enc;
    enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, o.quantPosition);
    enc.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, o.quantTexcoord);
    enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, o.quantNormal);
    enc.SetSpeedOptions(o.dracoSpeed, o.dracoSpeed);
    enc.SetTrackEncodedProperties(true);
    draco::EncoderBuffer out;
    draco::Status st = enc.EncodeMeshToBuffer(dm, &out);
    if (!st.ok()) throw SolverError(path + ": Draco encoding of '" + L.name + "' failed: " + st.error_msg_string());
    size_t points = enc.num_encoded_points(), faces = enc.num_encoded_faces();
    int view = b.view(out.data(), out.size(), 0);
    json attrs;
    json pa = floatAccessor(L.positions, 3, true);
    pa["count"] = points;
    attrs["POSITION"] = b.accessor(pa);
    json na = floatAccessor(L.normals, 3, false);
    na["count"] = points;
    attrs["NORMAL"] = b.accessor(na);
    json ta = floatAccessor(L.uvs, 2, false);
    ta["count"] = points;
    attrs["TEXCOORD_0"] = b.accessor(ta);
    int ia = b.accessor({{"componentType", points < 65536 ? kUnsignedShort : kUnsignedInt}, {"count", faces * 3}, {"type", "SCALAR"}});
    json ext = {{"bufferView", view}, {"attributes", {{"POSITION", pid}, {"NORMAL", nid}, {"TEXCOORD_0", tid}}}};
    return {{"attributes", attrs}, {"indices", ia}, {"mode", 4}, {"extensions", {{kDraco, ext}}}};
}

std::string lowerExt(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    return e;
}

}  // namespace

LodChainWriteStats writeLodChain(const std::string& path, const std::vector<LodLevelData>& levels,
                                 const std::vector<double>& screenCoverage, const LodChainWriteOptions& options) {
    std::string ext = lowerExt(path);
    bool glb = ext == ".glb";
    if (!glb && ext != ".gltf") throw IOError(path + ": output must end in .glb or .gltf");
    if (levels.empty()) throw InvalidInput(path + ": no level to write");
    if (!screenCoverage.empty() && screenCoverage.size() != levels.size())
        throw InvalidInput(path + ": " + std::to_string(screenCoverage.size()) + " screen coverage values for " +
                           std::to_string(levels.size()) + " levels");
    for (const LodLevelData& L : levels) checkLevel(path, L);

    LodChainWriteStats stats;
    Buffer b;
    json meshes = json::array(), nodes = json::array(), materials = json::array(), textures = json::array(),
         images = json::array();
    std::vector<std::pair<std::string, const Image*>> sideImages;
    std::string stem = std::filesystem::path(path).stem().string();
    for (size_t i = 0; i < levels.size(); ++i) {
        const LodLevelData& L = levels[i];
        size_t before = b.bin.size();
        json prim = options.draco ? dracoPrimitive(b, L, options, path) : plainPrimitive(b, L);
        stats.levelGeometryBytes.push_back(b.bin.size() - before);
        prim["material"] = i;
        meshes.push_back({{"name", L.name}, {"primitives", json::array({prim})}});
        json mat = {{"name", L.name},
                    {"pbrMetallicRoughness",
                     {{"baseColorTexture", {{"index", i}}}, {"metallicFactor", L.metallicFactor}, {"roughnessFactor", L.roughnessFactor}}}};
        if (L.doubleSided) mat["doubleSided"] = true;
        materials.push_back(mat);
        textures.push_back({{"source", i}, {"sampler", 0}});
        std::string mime = sniffImageMime(L.image.encoded.data(), L.image.encoded.size());
        if (mime.empty()) mime = "image/png";
        json img = {{"name", L.name}};
        if (glb || options.embedImages) {
            img["bufferView"] = b.view(L.image.encoded.data(), L.image.encoded.size(), 0);
            img["mimeType"] = mime;
        } else {
            std::string file = stem + "_" + L.name + (mime == "image/jpeg" ? ".jpg" : ".png");
            img["uri"] = file;
            sideImages.emplace_back(file, &L.image);
        }
        stats.levelImageBytes.push_back(L.image.encoded.size());
        images.push_back(img);
        nodes.push_back({{"name", L.name}, {"mesh", i}});
    }

    json root;
    root["asset"] = {{"version", "2.0"}, {"generator", options.generator}};
    std::vector<std::string> used;
    if (levels.size() > 1) {
        std::vector<size_t> ids;
        for (size_t i = 1; i < levels.size(); ++i) ids.push_back(i);
        nodes[0]["extensions"][kLod] = {{"ids", ids}};
        if (!screenCoverage.empty()) nodes[0]["extras"]["MSFT_screencoverage"] = screenCoverage;
        used.push_back(kLod);
    }
    if (options.draco) {
        used.push_back(kDraco);
        root["extensionsRequired"] = json::array({kDraco});
    }
    if (!used.empty()) {
        std::sort(used.begin(), used.end());
        root["extensionsUsed"] = used;
    }
    root["scene"] = 0;
    root["scenes"] = json::array({json{{"nodes", json::array({0})}}});
    root["nodes"] = nodes;
    root["meshes"] = meshes;
    root["materials"] = materials;
    root["textures"] = textures;
    root["images"] = images;
    // Linear-mipmap-linear minification: the gutters are sized for the mip levels this uses.
    root["samplers"] = json::array({json{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 33071}, {"wrapT", 33071}}});
    while (b.bin.size() % 4) b.bin.push_back('\0');
    std::string binName = stem + ".bin";
    json buf = {{"byteLength", b.bin.size()}};
    if (!glb) buf["uri"] = binName;
    root["buffers"] = json::array({buf});
    root["bufferViews"] = b.views;
    root["accessors"] = b.accessors;

    std::string text = root.dump();
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    for (const auto& [file, img] : sideImages) {
        writeFileAtomic((dir / file).string(), std::string(img->encoded.begin(), img->encoded.end()));
        stats.fileBytes += img->encoded.size();
    }
    if (glb) {
        while (text.size() % 4) text.push_back(' ');
        auto u32 = [](std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
        size_t total = 12 + 8 + text.size() + 8 + b.bin.size();
        if (total > 0xFFFFFFFFull) throw IOError(path + ": GLB would exceed 4 GiB");
        std::string out;
        out.reserve(total);
        u32(out, 0x46546C67u);
        u32(out, 2);
        u32(out, uint32_t(total));
        u32(out, uint32_t(text.size()));
        u32(out, 0x4E4F534Au);
        out += text;
        u32(out, uint32_t(b.bin.size()));
        u32(out, 0x004E4942u);
        out += b.bin;
        writeFileAtomic(path, out);
        stats.fileBytes += out.size();
    } else {
        writeFileAtomic((dir / binName).string(), b.bin);
        writeFileAtomic(path, text);
        stats.fileBytes += b.bin.size() + text.size();
    }
    return stats;
}

Image encodeImage(const std::vector<float>& rgb, int width, int height, ImageFormat format, int jpegQuality,
                  const std::string& name) {
    if (width <= 0 || height <= 0 || rgb.size() != size_t(width) * size_t(height) * 3)
        throw InvalidInput("encodeImage: pixel array does not match " + std::to_string(width) + "x" + std::to_string(height));
    std::vector<unsigned char> px(rgb.size());
    for (size_t i = 0; i < rgb.size(); ++i) {
        float v = std::isfinite(rgb[i]) ? std::clamp(rgb[i], 0.f, 1.f) : 0.f;
        px[i] = static_cast<unsigned char>(std::lround(v * 255.f));
    }
    bool jpeg = format == ImageFormat::Jpeg;
    std::string fname = jpeg ? "atlas.jpg" : "atlas.png";
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput vec(bytes);
    OIIO::Filesystem::IOProxy* proxy = &vec;
    auto out = OIIO::ImageOutput::create(fname, proxy);
    if (!out) throw IOError("encodeImage: no " + std::string(jpeg ? "JPEG" : "PNG") + " encoder: " + OIIO::geterror());
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    if (jpeg) spec.attribute("Compression", "jpeg:" + std::to_string(std::clamp(jpegQuality, 1, 100)));
    spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    if (!out->open(fname, spec) || !out->write_image(OIIO::TypeDesc::UINT8, px.data()) || !out->close())
        throw IOError("encodeImage: cannot encode: " + out->geterror());
    Image img;
    img.name = name;
    img.mimeType = jpeg ? "image/jpeg" : "image/png";
    img.encoded.assign(bytes.begin(), bytes.end());
    img.width = width;
    img.height = height;
    img.channels = 3;
    return img;
}

}  // namespace lodbake

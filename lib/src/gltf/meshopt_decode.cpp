// EXT_meshopt_compression: compressed bufferViews decoded with meshoptimizer's decoders
// (https://github.com/KhronosGroup/glTF/tree/main/extensions/2.0/Vendor/EXT_meshopt_compression).
// A compressed view stores `count` elements of `byteStride` bytes as a vertex stream (ATTRIBUTES,
// then an optional filter applied in place), a triangle index stream (TRIANGLES) or an index
// sequence (INDICES); the decoded bytes replace the view's (fallback) bytes.
#include "gltf/meshopt_decode.h"

#include <string>
#include <vector>

#include <meshoptimizer.h>
#include <tiny_gltf.h>

namespace lodbake::gltf_detail {

using json = nlohmann::json;

namespace {

constexpr const char* kExt = "EXT_meshopt_compression";

const json* meshoptExtension(const json& o) {
    if (!o.is_object() || !o.contains("extensions") || !o["extensions"].is_object()) return nullptr;
    auto it = o["extensions"].find(kExt);
    return it == o["extensions"].end() ? nullptr : &*it;
}

size_t juint(const ReadContext& c, const json& o, const char* key, bool required, const std::string& what) {
    if (!o.contains(key)) {
        if (required) fail(c, what + ": missing " + key);
        return 0;
    }
    if (!o[key].is_number_unsigned()) fail(c, what + ": " + key + " is not a non-negative integer");
    return o[key].get<size_t>();
}

// The decoded bytes of one compressed view.
std::vector<unsigned char> decodeView(const ReadContext& c, const tinygltf::Model& model, const json& ext, const std::string& w) {
    if (!ext.is_object()) fail(c, w + ": not an object");
    const size_t buffer = juint(c, ext, "buffer", true, w);
    const size_t offset = juint(c, ext, "byteOffset", false, w);
    const size_t length = juint(c, ext, "byteLength", true, w);
    const size_t stride = juint(c, ext, "byteStride", true, w);
    const size_t count = juint(c, ext, "count", true, w);
    const std::string mode = ext.value("mode", std::string());
    const std::string filter = ext.value("filter", std::string("NONE"));
    if (buffer >= model.buffers.size()) fail(c, w + ": buffer " + std::to_string(buffer) + " does not exist");
    const std::vector<unsigned char>& data = model.buffers[buffer].data;
    if (offset > data.size() || length > data.size() - offset)
        fail(c, w + ": compressed bytes (offset " + std::to_string(offset) + ", length " + std::to_string(length) +
                    ") exceed buffer " + std::to_string(buffer) + " (" + std::to_string(data.size()) + " bytes)");
    // The decoders write count * stride bytes; the stream cannot describe more than a few bytes
    // per element below its own size, so a count far beyond it is malformed, not a reason to allocate.
    if (stride == 0 || count > (size_t(1) << 28) || stride > 256) fail(c, w + ": byteStride " + std::to_string(stride) + " or count " + std::to_string(count) + " out of range");
    std::vector<unsigned char> out(count * stride);
    const unsigned char* src = data.data() + offset;
    int rc = 0;
    if (mode == "ATTRIBUTES") {
        if (stride % 4) fail(c, w + ": ATTRIBUTES byteStride " + std::to_string(stride) + " is not a multiple of 4");
        rc = meshopt_decodeVertexBuffer(out.data(), count, stride, src, length);
        if (rc == 0) {
            if (filter == "OCTAHEDRAL") {
                if (stride != 4 && stride != 8) fail(c, w + ": OCTAHEDRAL filter needs byteStride 4 or 8");
                meshopt_decodeFilterOct(out.data(), count, stride);
            } else if (filter == "QUATERNION") {
                if (stride != 8) fail(c, w + ": QUATERNION filter needs byteStride 8");
                meshopt_decodeFilterQuat(out.data(), count, stride);
            } else if (filter == "EXPONENTIAL") {
                meshopt_decodeFilterExp(out.data(), count, stride);
            } else if (filter != "NONE") {
                fail(c, w + ": unknown filter '" + filter + "'");
            }
        }
    } else if (mode == "TRIANGLES" || mode == "INDICES") {
        if (stride != 2 && stride != 4) fail(c, w + ": " + mode + " byteStride " + std::to_string(stride) + " is not 2 or 4");
        if (filter != "NONE") fail(c, w + ": filter " + filter + " on " + mode + " data");
        if (mode == "TRIANGLES") {
            if (count % 3) fail(c, w + ": TRIANGLES count " + std::to_string(count) + " is not a multiple of 3");
            rc = meshopt_decodeIndexBuffer(out.data(), count, stride, src, length);
        } else {
            rc = meshopt_decodeIndexSequence(out.data(), count, stride, src, length);
        }
    } else {
        fail(c, w + ": unknown mode '" + mode + "'");
    }
    if (rc != 0) fail(c, w + ": cannot decode the " + mode + " stream (meshoptimizer error " + std::to_string(rc) + ")");
    return out;
}

}  // namespace

bool hideMeshoptFallbackBuffers(const json& root, std::optional<json>& patched) {
    if (!root.contains("buffers") || !root["buffers"].is_array()) return false;
    bool changed = false;
    for (size_t i = 0; i < root["buffers"].size(); ++i) {
        const json& b = root["buffers"][i];
        const json* ext = meshoptExtension(b);
        if (!ext || !ext->is_object() || !ext->value("fallback", false) || b.contains("uri")) continue;
        if (!patched) patched = root;
        changed = true;
        // One zero byte: tinygltf refuses an empty data URI. No view reads it (compressed views are
        // re-pointed at their decoded bytes; any other view into it is out of range, as it should be).
        (*patched)["buffers"][i] = json{{"byteLength", 1}, {"uri", "data:application/octet-stream;base64,AA=="}};
    }
    return changed;
}

void decodeMeshoptViews(const ReadContext& c, tinygltf::Model& model) {
    if (!c.root.contains("bufferViews") || !c.root["bufferViews"].is_array()) return;
    const json& views = c.root["bufferViews"];
    for (size_t i = 0; i < views.size() && i < model.bufferViews.size(); ++i) {
        const json* ext = meshoptExtension(views[i]);
        if (!ext) continue;
        const std::string w = "bufferView " + std::to_string(i) + ": " + kExt;
        tinygltf::Buffer decoded;
        decoded.data = decodeView(c, model, *ext, w);
        tinygltf::BufferView& view = model.bufferViews[i];
        // The view's own byteStride (if any) is the decoded layout's; the stream's stride is the
        // element size the decoder wrote, which the spec requires to match.
        view.buffer = int(model.buffers.size());
        view.byteOffset = 0;
        view.byteLength = decoded.data.size();
        model.buffers.push_back(std::move(decoded));
    }
}

}  // namespace lodbake::gltf_detail

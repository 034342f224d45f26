// The bytes tinygltf reads besides the JSON (gltf_files.h).
#include "gltf/gltf_files.h"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "lodbake/core/errors.h"

namespace lodbake::gltf_detail {
namespace {

// The URI buffer 0 gets in the JSON tinygltf parses when its bytes are handed over. No file is
// looked up for it, whatever the directory holds.
const std::string kBinChunkUri = "lodbake-glb-bin-chunk";

bool namesBinChunk(const std::string& path) {
    const std::string tail = "/" + kBinChunkUri;
    return path == kBinChunkUri ||
           (path.size() > tail.size() && path.compare(path.size() - tail.size(), tail.size(), tail) == 0);
}

bool fileExists(const std::string& path, void* userData) {
    if (userData && namesBinChunk(path)) return true;
    return tinygltf::FileExists(path, nullptr);
}

std::string expandFilePath(const std::string& path, void* userData) {
    if (userData && namesBinChunk(path)) return path;
    return tinygltf::ExpandFilePath(path, nullptr);
}

// tinygltf's default reader sizes the buffer from tellg, which is -1 for a directory (a URI "/" or
// "."): a request for 2^63 bytes. Only regular files are read (a FIFO or device would block or
// never end); anything else is a read error.
bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* userData) {
    auto* bin = static_cast<GlbBinChunk*>(userData);
    if (bin && namesBinChunk(path)) {
        out->swap(bin->bytes);
        return true;
    }
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        if (err) *err += "not a regular file";
        return false;
    }
    try {
        *out = readFileBytes(path);
    } catch (const IOError& e) {
        if (err) *err += e.what();
        return false;
    }
    return true;
}

uint32_t u32At(const std::vector<unsigned char>& bytes, size_t at) {
    uint32_t v = 0;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
}

}  // namespace

std::vector<unsigned char> readFileBytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw IOError(path + ": cannot open: " + std::strerror(errno));
    // Block reads into a vector sized from the file (a stream iterator copies byte by byte: seconds
    // for a stage's 100 MB intermediate); a file that is not regular just grows the vector.
    std::vector<unsigned char> bytes;
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (!ec) bytes.reserve(size_t(size));
    char block[1 << 16];
    while (f.read(block, sizeof block) || f.gcount() > 0) bytes.insert(bytes.end(), block, block + f.gcount());
    if (f.bad()) throw IOError(path + ": cannot read: " + std::strerror(errno));
    return bytes;
}

bool takeGlbBinChunk(const nlohmann::json& root, std::optional<nlohmann::json>& patched, std::vector<unsigned char>& glb,
                     GlbBinChunk& bin) {
    constexpr uint32_t kJson = 0x4E4F534Au, kBin = 0x004E4942u;
    if (glb.size() < 20) return false;
    const uint64_t total = u32At(glb, 8), jsonLength = u32At(glb, 12);
    const uint64_t binHeader = 20 + jsonLength;
    if (total > glb.size() || u32At(glb, 16) != kJson || jsonLength == 0 || binHeader % 4 != 0 || binHeader + 8 > total)
        return false;
    const uint64_t binLength = u32At(glb, size_t(binHeader));
    if (u32At(glb, size_t(binHeader) + 4) != kBin || binLength < 4 || binLength % 4 != 0 || binHeader + 8 + binLength > total)
        return false;
    const nlohmann::json& seen = patched ? *patched : root;
    if (!seen.is_object() || !seen.contains("buffers") || !seen["buffers"].is_array() || seen["buffers"].empty()) return false;
    const nlohmann::json& buffers = seen["buffers"];
    for (size_t i = 0; i < buffers.size(); ++i)
        if (!buffers[i].is_object() || buffers[i].contains("uri") != (i > 0)) return false;
    const nlohmann::json& length = buffers[0].contains("byteLength") ? buffers[0]["byteLength"] : nlohmann::json();
    if (!length.is_number_unsigned() || length.get<uint64_t>() == 0 || length.get<uint64_t>() > binLength) return false;

    if (!patched) patched = root;
    (*patched)["buffers"][0]["uri"] = kBinChunkUri;
    const size_t at = size_t(binHeader) + 8;
    glb.erase(glb.begin(), glb.begin() + long(at));
    glb.resize(length.get<size_t>());
    bin.bytes = std::move(glb);
    return true;
}

tinygltf::FsCallbacks fileCallbacks(GlbBinChunk* bin) {
    return {&fileExists, &expandFilePath, &readWholeFile, &tinygltf::WriteWholeFile, bin};
}

}  // namespace lodbake::gltf_detail

// Helpers that write small synthetic glTF files for the io tests: a JSON document plus one
// binary buffer, saved as .gltf (+ .bin or data URI) or .glb.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

namespace lodbake::testing {

// A fresh, empty temporary folder per call (removed by the caller if wanted).
inline std::filesystem::path tempDir(const std::string& name) {
    std::filesystem::path d = std::filesystem::temp_directory_path() / ("lodbake_io_test_" + std::to_string(::getpid())) / name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

inline void writeBytes(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream f(p, std::ios::binary);
    f.write(bytes.data(), std::streamsize(bytes.size()));
}

inline std::string readBytes(const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

inline std::string base64(const std::string& in) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < in.size(); i += 3) {
        uint32_t v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8) | uint8_t(in[i + 2]);
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
    }
    if (i + 1 == in.size()) {
        uint32_t v = uint8_t(in[i]) << 16;
        out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
    } else if (i + 2 == in.size()) {
        uint32_t v = (uint8_t(in[i]) << 16) | (uint8_t(in[i + 1]) << 8);
        out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
    }
    return out;
}

// Builds a glTF document: buffer views/accessors over one binary buffer, meshes, nodes.
struct TestGltf {
    nlohmann::json j;
    std::string bin;

    TestGltf() {
        j["asset"] = {{"version", "2.0"}};
        j["scene"] = 0;
        j["scenes"] = nlohmann::json::array({{{"nodes", nlohmann::json::array()}}});
    }

    int view(const void* data, size_t bytes, int stride = 0) {
        while (bin.size() % 4) bin.push_back('\0');
        nlohmann::json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (stride) v["byteStride"] = stride;
        bin.append(static_cast<const char*>(data), bytes);
        j["bufferViews"].push_back(v);
        return int(j["bufferViews"].size()) - 1;
    }

    int accessor(int view, size_t offset, int componentType, size_t count, const std::string& type, bool normalized = false) {
        nlohmann::json a = {{"bufferView", view}, {"byteOffset", offset}, {"componentType", componentType}, {"count", count}, {"type", type}};
        if (normalized) a["normalized"] = true;
        j["accessors"].push_back(a);
        return int(j["accessors"].size()) - 1;
    }

    // Tightly packed accessor over its own view; T is the component C type.
    template <class T>
    int add(const std::vector<T>& data, int componentType, const std::string& type, bool normalized = false) {
        int comps = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : 4;
        int v = view(data.data(), data.size() * sizeof(T));
        return accessor(v, 0, componentType, data.size() / size_t(comps), type, normalized);
    }

    int addMesh(const nlohmann::json& primitives) {
        j["meshes"].push_back({{"primitives", primitives}});
        return int(j["meshes"].size()) - 1;
    }

    int addNode(const nlohmann::json& node, bool root = true) {
        j["nodes"].push_back(node);
        int n = int(j["nodes"].size()) - 1;
        if (root) j["scenes"][0]["nodes"].push_back(n);
        return n;
    }

    void finishBuffer(const std::string& uri) {
        while (bin.size() % 4) bin.push_back('\0');
        if (bin.empty()) return;
        nlohmann::json b = {{"byteLength", bin.size()}};
        if (!uri.empty()) b["uri"] = uri;
        j["buffers"] = nlohmann::json::array({b});
    }

    // .gltf with the buffer in NAME.bin beside it.
    std::string writeGltf(const std::filesystem::path& dir, const std::string& name) {
        finishBuffer(name + ".bin");
        writeBytes(dir / (name + ".bin"), bin);
        std::string p = (dir / (name + ".gltf")).string();
        writeBytes(p, j.dump(1));
        return p;
    }

    // .gltf with the buffer as a base64 data URI.
    std::string writeGltfDataUri(const std::filesystem::path& dir, const std::string& name) {
        finishBuffer("data:application/octet-stream;base64," + base64(bin));
        std::string p = (dir / (name + ".gltf")).string();
        writeBytes(p, j.dump());
        return p;
    }

    std::string glbBytes() {
        finishBuffer("");
        return glbOf(j, bin);
    }

    // A GLB of this JSON and BIN chunk (none when empty), whatever buffer 0 declares.
    static std::string glbOf(const nlohmann::json& json, const std::string& binChunk) {
        std::string text = json.dump();
        while (text.size() % 4) text.push_back(' ');
        auto u32 = [](std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
        std::string out;
        u32(out, 0x46546C67u);
        u32(out, 2);
        u32(out, uint32_t(12 + 8 + text.size() + (binChunk.empty() ? 0 : 8 + binChunk.size())));
        u32(out, uint32_t(text.size()));
        u32(out, 0x4E4F534Au);
        out += text;
        if (!binChunk.empty()) {
            u32(out, uint32_t(binChunk.size()));
            u32(out, 0x004E4942u);
            out += binChunk;
        }
        return out;
    }

    std::string writeGlb(const std::filesystem::path& dir, const std::string& name) {
        std::string p = (dir / name).string();
        writeBytes(p, glbBytes());
        return p;
    }
};

// A single triangle (0,0,0) (1,0,0) (0,1,0): counter-clockwise seen from +z.
inline std::vector<float> unitTrianglePositions() { return {0, 0, 0, 1, 0, 0, 0, 1, 0}; }

// Unit cube as 24 glTF vertices (4 per face, face normals) and 36 indices.
inline void cubeData(std::vector<float>& pos, std::vector<float>& nrm, std::vector<uint16_t>& idx) {
    const float n[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int f = 0; f < 6; ++f) {
        int a = f / 2;                 // axis of the normal
        float s = n[f][a];             // +1 / -1
        int u = (a + 1) % 3, v = (a + 2) % 3;
        float corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        uint16_t base = uint16_t(pos.size() / 3);
        for (auto& c : corners) {
            float p[3];
            p[a] = s > 0 ? 1.f : 0.f;
            p[u] = c[0];
            p[v] = c[1];
            pos.insert(pos.end(), p, p + 3);
            nrm.insert(nrm.end(), n[f], n[f] + 3);
        }
        // (u, v) x order gives +a normal; flip for negative faces.
        if (s > 0) idx.insert(idx.end(), {base, uint16_t(base + 1), uint16_t(base + 2), base, uint16_t(base + 2), uint16_t(base + 3)});
        else idx.insert(idx.end(), {base, uint16_t(base + 2), uint16_t(base + 1), base, uint16_t(base + 3), uint16_t(base + 2)});
    }
}

}  // namespace lodbake::testing

namespace lodbake::testing {

// A primitive object; -1 leaves indices / mode / material out.
inline nlohmann::json prim(const nlohmann::json& attributes, int indices = -1, int mode = -1, int material = -1) {
    nlohmann::json p = {{"attributes", attributes}};
    if (indices >= 0) p["indices"] = indices;
    if (mode >= 0) p["mode"] = mode;
    if (material >= 0) p["material"] = material;
    return p;
}

// Adds a mesh made of `primitives` and a root node instancing it (extra node fields in `node`).
inline int meshNode(TestGltf& g, const std::vector<nlohmann::json>& primitives, nlohmann::json node = nlohmann::json::object()) {
    nlohmann::json arr = nlohmann::json::array();
    for (const auto& p : primitives) arr.push_back(p);
    node["mesh"] = g.addMesh(arr);
    return g.addNode(node);
}

}  // namespace lodbake::testing

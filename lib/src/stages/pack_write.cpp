// Writing a packed LOD chain (pack_write.h): one MSFT_lod file, or a file per level and the manifest.
#include "lodbake/stages/pack_write.h"

#include <filesystem>

#include <nlohmann/json.hpp>

#include "lodbake/gltf/gltf.h"

namespace lodbake {
namespace {

// Level k of one written file's stats (and the file's warnings, once: k == 0) into the pack's.
void appendLevelStats(PackWriteStats& st, const LodChainWriteStats& w, size_t k) {
    st.levelBytes.push_back(w.levelGeometryBytes[k] + w.levelImageBytes[k]);
    st.levelGeometryBytes.push_back(w.levelGeometryBytes[k]);
    st.levelImageBytes.push_back(w.levelImageBytes[k]);
    st.cacheBefore.push_back(w.levelCacheBefore[k]);
    st.cacheAfter.push_back(w.levelCacheAfter[k]);
    if (k == 0) st.warnings.insert(st.warnings.end(), w.warnings.begin(), w.warnings.end());
}

}  // namespace

PackWriteStats writePackResult(const std::string& path, const PackResult& result, const PackWriteOptions& options) {
    PackWriteStats st;
    LodChainWriteOptions chain = options.chain;
    chain.variants = result.variants;
    if (!options.split) {
        LodChainWriteStats w = writeLodChain(path, result.levels, result.screenCoverage, chain, &result.rig, &result.morph,
                                             &result.scene, result.original ? &*result.original : nullptr);
        st.files.push_back(path);
        for (size_t k = 0; k < result.reports.size(); ++k) appendLevelStats(st, w, k);
        st.totalBytes = w.fileBytes;
        return st;
    }
    namespace fs = std::filesystem;
    fs::path p(path);
    std::string stem = (p.parent_path() / p.stem()).string(), ext = p.extension().string();
    nlohmann::json manifest;
    manifest["levels"] = nlohmann::json::array();
    const size_t first = result.original ? 1 : 0;  // index in result.levels of LOD0 - first
    for (size_t k = 0; k < result.reports.size(); ++k) {
        std::string file = stem + ".lod" + std::to_string(k) + ext;
        const bool hero = result.original && k == 0;
        LodChainWriteStats w = hero ? writeLodChain(file, {}, {}, chain, &result.rig, &result.morph, &result.scene, &*result.original)
                                    : writeLodChain(file, {result.levels[k - first]}, {}, chain, &result.rig, &result.morph, &result.scene);
        st.files.push_back(file);
        appendLevelStats(st, w, 0);
        st.totalBytes += w.fileBytes;
        manifest["levels"].push_back({{"file", fs::path(file).filename().string()},
                                      {"screenCoverage", result.screenCoverage[k]},
                                      {"triangles", hero ? result.original->triangles : result.levels[k - first].indices.size() / 3}});
    }
    manifest["cutoff"] = result.screenCoverage.back();
    manifest["screenCoverage"] = result.screenCoverage;
    manifest["note"] = "level k is drawn while the bounding sphere's projected height / viewport height >= screenCoverage[k]; "
                       "below the last value nothing is drawn (MSFT_screencoverage semantics)";
    std::string mpath = stem + ".lods.json";
    std::string text = manifest.dump(2) + "\n";
    writeFileAtomic(mpath, text);
    st.files.push_back(mpath);
    st.totalBytes += text.size();
    return st;
}

}  // namespace lodbake

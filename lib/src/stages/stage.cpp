// What every stage shares (stage.h): loading, atomic writing, progress and the JSON report.
#include "lodbake/stages/stage.h"

#include <cstdarg>
#include <cstdio>

#include "lodbake/core/free_pages.h"
#include "lodbake/core/timing.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/texture/codec.h"

namespace lodbake {

Asset loadStageInput(const StageCommon& common, double& seconds, std::optional<Multires>* multires,
                     void (*check)(Asset&, ImageCheck)) {
    Clock::time_point t0 = Clock::now();
    Asset asset = common.inputBytes ? readGltfBytes(common.input, std::move(*common.inputBytes), {}, multires)
                                    : readGltf(common.input, {}, multires);
    if (check) check(asset, common.inputImagesDecoded ? ImageCheck::Header : ImageCheck::Decode);
    keepFreedPages(asset.mesh.triangleCount() < kKeepFreedPagesBelow);
    returnFreedPages();  // the file's bytes and the parser's tree: the stage's peak comes later
    seconds = secondsSince(t0);
    if (common.warning)
        for (const std::string& w : asset.warnings) common.warning(w);
    return asset;
}

double writeStageOutput(const StageCommon& common, const Asset& asset, const Multires* multires, const std::string& tool) {
    Clock::time_point t0 = Clock::now();
    // The encoded file is as large as the asset again: it should not sit on the work's freed pages.
    returnFreedPages();
    WriteOptions options;
    options.generator = "lodbake " + tool + " 0.1.0";
    if (common.outputBytes)
        *common.outputBytes = encodeGlb(common.output, asset, multires, options);
    else
        writeGltf(common.output, asset, multires, options);
    return secondsSince(t0);
}

void writeReport(const std::string& path, const nlohmann::json& report) {
    writeFileAtomic(path, report.dump(2) + "\n");
}

void appendf(std::string& out, const char* format, ...) {
    va_list args;
    va_start(args, format);
    va_list copy;
    va_copy(copy, args);
    int n = std::vsnprintf(nullptr, 0, format, copy);
    va_end(copy);
    if (n > 0) {
        size_t old = out.size();
        out.resize(old + size_t(n) + 1);
        std::vsnprintf(&out[old], size_t(n) + 1, format, args);
        out.resize(old + size_t(n));
    }
    va_end(args);
}

}  // namespace lodbake

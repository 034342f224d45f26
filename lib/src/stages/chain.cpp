// The whole chain in one process (chain.h): each stage run in turn on the previous one's bytes.
#include "lodbake/stages/chain.h"

#include <filesystem>

#include "chain_review.h"
#include "lodbake/core/free_pages.h"
#include "lodbake/core/timing.h"
#include "lodbake/gltf/gltf.h"

namespace lodbake {
namespace {

using Bytes = std::vector<unsigned char>;

// Where one stage's output goes: a file in keepIntermediates, or bytes named "memory:NAME".
struct Intermediate {
    std::string path;
    Bytes bytes;
    bool imagesDecoded = false;  // its images were decoded in full by the stage that wrote it or an earlier one

    // Frees the bytes once the next stage has read them: a million-triangle intermediate holds
    // hundreds of megabytes that would otherwise stay alive under every later stage's peak.
    void release() { Bytes().swap(bytes); }
};

struct ChainRun {
    ChainRun(const ChainSettings& s, std::string stemName) : settings(s), stem(std::move(stemName)) {}
    const ChainSettings& settings;
    std::string stem;
    nlohmann::json reports = nlohmann::json::array();
    nlohmann::json intermediates = nlohmann::json::array();
    std::vector<std::string> warnings;
    std::string statistics;

    // The stage's common settings: the chain's, with this stage's paths, bytes and callbacks.
    StageCommon common(const std::string& stage, const std::string& input, const std::string& output) {
        const StageCommon& c = settings.common;
        StageCommon s;
        s.input = input;
        s.output = output;
        s.verbose = c.verbose;
        s.threads = c.threads;
        if (settings.progress) s.progress = [this, stage](double f) { return settings.progress(stage, f); };
        s.warning = [this, stage](const std::string& w) {
            warnings.push_back(stage + ": " + w);
            if (settings.common.warning) settings.common.warning(stage + ": " + w);
        };
        return s;
    }

    std::string intermediatePath(const char* suffix) const {
        std::string name = stem + suffix;
        if (settings.keepIntermediates.empty()) return "memory:" + name;
        return (std::filesystem::path(settings.keepIntermediates) / name).string();
    }

    // Runs one stage that reads `in` (null: the chain's input file; the stage takes its bytes) and
    // writes `out` (null: the chain's output file).
    template <class Settings, class Stage>
    void run(const std::string& stage, Settings s, Intermediate* in, Intermediate* out, Stage runStage) {
        s.common = common(stage, in ? in->path : settings.common.input, out ? out->path : settings.common.output);
        if (in) {
            s.common.inputBytes = &in->bytes;
            s.common.inputImagesDecoded = in->imagesDecoded;
        }
        if (out) s.common.outputBytes = &out->bytes;
        StageResult r = runStage(s);
        if (out && !settings.keepIntermediates.empty()) {
            writeFileAtomic(out->path, {std::string_view(reinterpret_cast<const char*>(out->bytes.data()), out->bytes.size())});
            intermediates.push_back(out->path);
        }
        reports.push_back(std::move(r.report));
        if (settings.common.verbose) statistics += stage + ":\n" + r.statistics;
        returnFreedPages();  // the next stage's peak does not sit on this one's freed pages
    }
};

}  // namespace

StageResult runChain(const ChainSettings& s) {
    Clock::time_point t0 = Clock::now();
    ChainRun chain(s, std::filesystem::path(s.common.input).stem().string());

    Intermediate multires{chain.intermediatePath(".mr.glb"), {}};
    chain.run("simplify", s.simplify, nullptr, &multires, runSimplify);
    // parameterize decodes every input image (the original's, which simplify passes on): the
    // stages after it read only images it or they checked, or wrote.
    Intermediate parameterized{chain.intermediatePath(".uv.glb"), {}, true};
    // texture-refine and pack bake from the original images, never from parameterize's atlas
    // image: it is baked only for an intermediate that is kept.
    ParameterizeSettings parameterize = s.parameterize;
    parameterize.bakeImage = parameterize.bakeImage && !s.keepIntermediates.empty();
    chain.run("parameterize", parameterize, &multires, &parameterized, runParameterize);
    multires.release();
    Intermediate* packInput = &parameterized;
    Intermediate refined{chain.intermediatePath(".tex.glb"), {}, true};
    if (s.runTextureRefine) {
        // pack reads the hierarchy's layouts and texture sizes, never its images: they are baked
        // only for an intermediate that is kept.
        TextureRefineSettings refine = s.textureRefine;
        refine.refine.bakeImages = refine.refine.bakeImages && !s.keepIntermediates.empty();
        chain.run("texture-refine", refine, &parameterized, &refined, runTextureRefine);
        parameterized.release();
        packInput = &refined;
    }
    PackSettings pack = s.pack;
    if (pack.pack.lod0 == Lod0::Original && pack.pack.original.empty()) pack.pack.original = s.common.input;  // the chain's own input
    chain.run("pack", pack, packInput, nullptr, runPack);

    StageResult out;
    out.report = {{"tool", "lodbake"},
                  {"input", s.common.input},
                  {"output", s.common.output},
                  {"stages", chain.reports},
                  {"intermediates", chain.intermediates},
                  {"warnings", chain.warnings},
                  {"time", {{"total", secondsSince(t0)}}}};
    HtmlPage page;
    if (!s.html.empty()) {
        const Clock::time_point review = Clock::now();
        std::function<bool(double)> progress;
        if (s.progress) progress = [&s](double f) { return s.progress("review", f); };
        page = reviewChain(s, out.report, progress);
        out.report["time"]["review"] = secondsSince(review);
        out.report["time"]["total"] = secondsSince(t0);
    }
    if (!s.common.report.empty()) writeReport(s.common.report, out.report);
    if (!s.html.empty()) writeHtmlReport(s.html, page, out.report);
    out.statistics = std::move(chain.statistics);
    return out;
}

}  // namespace lodbake

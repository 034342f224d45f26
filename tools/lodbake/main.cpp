// lodbake: the whole chain in one command (simplify -> parameterize -> texture-refine -> pack),
// in one process through the library (lodbake/stages/chain.h). Every stage's flags are the
// separate tools' own (common/stage_flags.h); texture-refine's that another stage also has take a
// "refine-" prefix (docs/lodbake.md).
#include <filesystem>
#include <memory>

#include "common/stage_flags.h"
#include "lodbake/stages/chain.h"

using namespace lodbake;

namespace {

struct Args {
    ChainSettings chain;
    cli::SimplifyFlags simplify;
    cli::ParameterizeFlags parameterize;
    cli::TextureRefineFlags textureRefine;
    cli::PackFlags pack;
    bool quiet = false;
};

Args parseArgs(int argc, char** argv, bool& proceed) {
    Args a;
    cli::ArgParser p("lodbake", "-i INPUT -o OUTPUT.lod.glb (--ratio R,... | --triangles N,... | --max-error E,...) [options]");
    p.addCommon(a.chain.common, a.quiet);
    p.option("--keep-intermediates", "DIR",
             "also write the intermediates as the tools name them: DIR/STEM.mr.glb, .uv.glb, .tex.glb",
             [&a](const std::string& v) {
                 if (v.empty()) throw UsageError("--keep-intermediates needs a folder");
                 a.chain.keepIntermediates = v;
             });
    p.flag("--no-texture-refine", "skip texture-refine: pack textures every level from parameterize's atlas",
           [&a] { a.chain.runTextureRefine = false; });
    p.section("simplify (docs/simplify.md)");
    cli::addSimplifyFlags(p, a.simplify);
    p.section("parameterize (docs/parameterize.md)");
    cli::addParameterizeFlags(p, a.parameterize);
    p.section("texture-refine (docs/texture-refine.md; its flags another stage also has take a refine- prefix)");
    cli::addTextureRefineFlags(p, a.textureRefine, "refine-");
    p.section("pack (docs/pack.md)");
    cli::addPackFlags(p, a.pack);
    p.exitCodes(
        "Exit codes: 0 success, 1 usage error, 2 unreadable or invalid input,\n"
        "            3 valid input but the operation is impossible, 4 internal failure.\n"
        "Fallbacks (a fold that survives parameterize, a chart the solver cannot flatten) are\n"
        "warnings in the report, never errors.\n");
    proceed = p.parse(argc, argv);
    return a;
}

void validate(Args& a) {
    cli::validateSimplify(a.simplify);
    cli::validateParameterize(a.parameterize);
    cli::validateTextureRefine(a.textureRefine);
    cli::validatePack(a.pack);
    cli::checkPaths(a.chain.common);
    const std::string& dir = a.chain.keepIntermediates;
    std::error_code ec;
    if (!dir.empty() && !std::filesystem::is_directory(dir, ec))
        throw IOError(dir + ": --keep-intermediates folder does not exist");
    a.chain.simplify = a.simplify.settings;
    a.chain.parameterize = a.parameterize.settings;
    a.chain.textureRefine = a.textureRefine.settings;
    a.chain.pack = a.pack.settings;
}

int run(Args& a) {
    validate(a);
    ChainSettings& s = a.chain;
    const bool draw = cli::progressEnabled(a.quiet);
    std::unique_ptr<cli::Progress> progress;
    std::string current;
    s.progress = [&](const std::string& stage, double fraction) {
        if (stage != current) {
            if (progress) progress->done();
            progress = std::make_unique<cli::Progress>("lodbake " + stage, draw);
            current = stage;
        }
        return (*progress)(fraction);
    };
    s.common.warning = [](const std::string& w) { cli::printWarning("lodbake", w); };
    StageResult result = runChain(s);
    if (progress) progress->done();
    std::fputs(result.statistics.c_str(), stdout);
    return cli::kOk;
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Args>("lodbake", argc, argv, parseArgs, run); }

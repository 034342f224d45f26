// lodbake: the whole chain in one command (simplify -> parameterize -> texture-refine -> pack),
// in one process through the library (lodbake/stages/chain.h). Every stage's flags are the
// separate tools' own (common/stage_flags.h); texture-refine's that another stage also has take a
// "refine-" prefix (docs/lodbake.md).
#include <unistd.h>

#include <filesystem>
#include <memory>

#include "batch.h"
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
    std::vector<std::string> inputs;  // -i and the positional inputs; several, or a folder: batch mode
    int jobs = 1;                     // batch mode: files baked at a time
    std::vector<std::string> passOn;  // batch mode: the flags each file's run gets
};

Args parseArgs(int argc, char** argv, bool& proceed) {
    Args a;
    cli::ArgParser p("lodbake", "[-i] INPUT... [-o OUTPUT.lod.glb | -o DIR/] [options]\n"
                                "  Bakes INPUT's LOD chain (simplify -> parameterize -> texture-refine -> pack). Without -o\n"
                                "  it is written beside the input as STEM.lod.glb; without a level flag the levels are 0.5,\n"
                                "  0.1 and 0.02 of the input's triangles. Several inputs or a folder (walked for .glb/.gltf)\n"
                                "  bake one chain each into -o DIR/ (or beside each input), -j at a time, and --report\n"
                                "  writes one summary (docs/schemas/lodbake-batch.schema.json). man lodbake; docs/lodbake.md.");
    p.addCommon(a.chain.common, a.quiet);
    p.positionals("INPUT", [&a](const std::string& v) { a.inputs.push_back(v); });
    p.option("-j,--jobs", "N", "batch mode: files baked at a time (default 1); each gets cores / N threads unless --threads is given",
             [&a](const std::string& v) {
                 a.jobs = cli::parseInt("--jobs", v);
                 if (a.jobs < 1) throw UsageError("--jobs must be >= 1");
             });
    p.option("--html", "FILE.html",
             "write a self-contained HTML report: every level measured against the input by compare, its renders beside "
             "the original's, the difference, its figures and atlas pages (docs/lodbake.md)",
             [&a](const std::string& v) {
                 if (v.empty()) throw UsageError("--html needs a file name");
                 a.chain.html = v;
             });
    p.option("--keep-intermediates", "DIR",
             "also write the intermediates as the tools name them: DIR/STEM.mr.glb, .uv.glb, .tex.glb",
             [&a](const std::string& v) {
                 if (v.empty()) throw UsageError("--keep-intermediates needs a folder");
                 a.chain.keepIntermediates = v;
             });
    p.flag("--no-texture-refine", "skip texture-refine: pack textures every level from parameterize's atlas",
           [&a] { a.chain.runTextureRefine = false; });
    p.section("simplify (docs/simplify.md)",
              "Stage flags: each stage's own, with the separate tool's name, default and checks (docs/lodbake.md).");
    cli::addSimplifyFlags(p, a.simplify);
    p.section("parameterize (docs/parameterize.md)");
    cli::addParameterizeFlags(p, a.parameterize);
    p.section("texture-refine (docs/texture-refine.md; its flags another stage also has take a refine- prefix)");
    cli::addTextureRefineFlags(p, a.textureRefine, "refine-");
    p.section("pack (docs/pack.md)");
    cli::addPackFlags(p, a.pack);
    p.describe("-i", "input glTF (.glb or .gltf), or a folder; -i may be left out; several inputs or a folder: batch mode");
    p.describe("-o", "the LOD chain, .glb or .gltf (+ .bin) by its extension (default: STEM.lod.glb beside the input); "
                     "DIR/ writes DIR/STEM.lod.glb");
    p.describe("--report", "write the JSON report to FILE.json (batch mode: one summary of every file; default none)");
    p.featured("Most used (the other flags follow)",
               {"-i", "-o", "--ratio", "--triangles", "--max-error", "--report", "--html", "-j", "--threads", "--max-size",
                "--normal-maps", "-q", "-v"});
    p.exitCodes(
        "Exit codes: 0 success, 1 usage error, 2 unreadable or invalid input,\n"
        "            3 valid input but the operation is impossible, 4 internal failure.\n"
        "Fallbacks (a fold that survives parameterize, a chart the solver cannot flatten) are\n"
        "warnings in the report, never errors.\n");
    proceed = p.parse(argc, argv);
    if (!a.chain.common.input.empty()) a.inputs.insert(a.inputs.begin(), a.chain.common.input);
    a.passOn = p.argumentsExcept({"-i", "-o", "--report", "-j", "-q", "-v", "-vv"});
    return a;
}

// The output when -o is absent (STEM.lod.glb beside the input) or names a folder (-o DIR/, or an
// existing folder): STEM is the input's file name without .glb/.gltf.
std::string defaultOutput(const std::string& input, const std::string& output) {
    namespace fs = std::filesystem;
    const std::string name = fs::path(input).stem().string() + ".lod.glb";
    std::error_code ec;
    if (output.empty()) return (fs::path(input).parent_path() / name).string();
    if (output.back() == '/' || fs::is_directory(output, ec)) return (fs::path(output) / name).string();
    return output;
}

void validateStageFlags(Args& a) {
    cli::validateSimplify(a.simplify);
    cli::validateParameterize(a.parameterize);
    cli::validateTextureRefine(a.textureRefine);
    cli::validatePack(a.pack);
}

// --html: a single-file chain (compare reads its levels back), a file in an existing folder, none
// of the other paths.
void validateHtml(const Args& a) {
    namespace fs = std::filesystem;
    const std::string& html = a.chain.html;
    if (html.empty()) return;
    if (a.pack.settings.write.split) throw UsageError("--html needs the chain in one file, not --split");
    std::error_code ec;
    const fs::path parent = fs::path(html).parent_path();
    if (!parent.empty() && !fs::is_directory(parent, ec))
        throw IOError(html + ": --html folder '" + parent.string() + "' does not exist");
    if (fs::is_directory(html, ec)) throw IOError(html + ": --html names a folder");
    const StageCommon& c = a.chain.common;
    for (const std::string& other : {c.input, c.output, c.report})
        if (!other.empty() && fs::weakly_canonical(other, ec) == fs::weakly_canonical(html, ec))
            throw UsageError("--html '" + html + "' is also the file '" + other + "'");
}

void validate(Args& a) {
    if (!a.chain.common.input.empty()) a.chain.common.output = defaultOutput(a.chain.common.input, a.chain.common.output);
    validateStageFlags(a);
    cli::checkPaths(a.chain.common);
    validateHtml(a);
    const std::string& dir = a.chain.keepIntermediates;
    std::error_code ec;
    if (!dir.empty() && !std::filesystem::is_directory(dir, ec))
        throw IOError(dir + ": --keep-intermediates folder does not exist");
    a.chain.simplify = a.simplify.settings;
    a.chain.parameterize = a.parameterize.settings;
    a.chain.textureRefine = a.textureRefine.settings;
    a.chain.pack = a.pack.settings;
}

// Several inputs, or a folder.
bool batchMode(const Args& a) {
    std::error_code ec;
    return a.inputs.size() > 1 || (a.inputs.size() == 1 && std::filesystem::is_directory(a.inputs[0], ec));
}

int runBatch(Args& a) {
    if (!a.chain.html.empty()) throw UsageError("--html takes one input (several inputs or a folder: run lodbake --html per file)");
    validateStageFlags(a);  // once here, rather than failing the same way in every child
    batch::collectInputs(a.inputs);  // every input exists and at least one is a glTF
    const std::string& out = a.chain.common.output;
    std::error_code ec;
    const std::string ext = std::filesystem::path(out).extension().string();
    if ((!out.empty() && std::filesystem::exists(out, ec) && !std::filesystem::is_directory(out, ec)) || ext == ".glb" || ext == ".gltf")
        throw UsageError("several inputs or a folder need -o DIR/ (a folder), not the file '" + out + "'");
    batch::BatchSettings b;
    b.inputs = a.inputs;
    b.outputDir = out;
    b.report = a.chain.common.report;
    b.passOn = a.passOn;
    b.jobs = a.jobs;
    b.progress = cli::progressEnabled(a.quiet);
    b.self = std::filesystem::read_symlink("/proc/self/exe", ec).string();
    if (b.self.empty()) throw IOError("cannot find the lodbake executable (/proc/self/exe) to run per file");
    return batch::runBatch(b);
}

int run(Args& a) {
    if (batchMode(a)) return runBatch(a);
    if (!a.inputs.empty()) a.chain.common.input = a.inputs[0];
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

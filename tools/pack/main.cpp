// pack: parameterized multiresolution glTF in, final glTF LOD chain out (MSFT_lod, one mesh /
// one material / one draw call per level, atlases sized for each level's screen size).
// Parses the flags (common/stage_flags.h) into PackSettings, validates them and runs the stage
// (lodbake/stages/pack.h).
#include "common/stage_flags.h"

using namespace lodbake;

namespace {

struct Args {
    cli::PackFlags flags;
    bool quiet = false;
};

Args parseArgs(int argc, char** argv, bool& proceed) {
    Args a;
    cli::ArgParser p("pack", "-i INPUT.uv.glb -o OUTPUT.lod.glb [options]");
    p.addCommon(a.flags.settings.common, a.quiet);
    cli::addPackFlags(p, a.flags);
    proceed = p.parse(argc, argv);
    return a;
}

int run(Args& a) {
    cli::validatePack(a.flags);
    const PackOptions& o = a.flags.settings.pack;
    if (o.lod0 == Lod0::Original && o.original.empty())
        throw UsageError("--lod0 original needs --original PATH (the asset simplify read)");
    cli::checkPaths(a.flags.settings.common);
    return cli::runStage("pack", a.flags.settings, a.quiet, runPack);
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Args>("pack", argc, argv, parseArgs, run); }

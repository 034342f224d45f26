// parameterize: multiresolution glTF in, same + new atlas UVs and one baked base-colour texture
// valid for every level (thesis 3.3). Parses the flags (common/stage_flags.h) into
// ParameterizeSettings, validates them and runs the stage (lodbake/stages/parameterize.h).
#include "common/stage_flags.h"

using namespace lodbake;

namespace {

struct Args {
    cli::ParameterizeFlags flags;
    bool quiet = false;
};

Args parseArgs(int argc, char** argv, bool& proceed) {
    Args a;
    cli::ArgParser p("parameterize", "-i INPUT.mr.glb -o OUTPUT.uv.glb [options]");
    p.addCommon(a.flags.settings.common, a.quiet);
    cli::addParameterizeFlags(p, a.flags);
    p.exitCodes(cli::parameterizeExitCodes());
    proceed = p.parse(argc, argv);
    return a;
}

int run(Args& a) {
    cli::validateParameterize(a.flags);
    cli::checkPaths(a.flags.settings.common);
    return cli::runStage("parameterize", a.flags.settings, a.quiet, runParameterize);
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Args>("parameterize", argc, argv, parseArgs, run); }

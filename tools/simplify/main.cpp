// simplify: any glTF in, multiresolution glTF out (half-edge collapse with region hierarchy).
// Parses the flags (common/stage_flags.h) into SimplifySettings, validates them and runs the stage
// (lodbake/stages/simplify.h).
#include "common/stage_flags.h"

using namespace lodbake;

namespace {

struct Args {
    cli::SimplifyFlags flags;
    bool quiet = false;
};

Args parseArgs(int argc, char** argv, bool& proceed) {
    Args a;
    cli::ArgParser p("simplify", "-i INPUT -o OUTPUT (--ratio R,... | --triangles N,... | --max-error E,...) [options]");
    p.addCommon(a.flags.settings.common, a.quiet);
    cli::addSimplifyFlags(p, a.flags);
    proceed = p.parse(argc, argv);
    return a;
}

int run(Args& a) {
    cli::checkPaths(a.flags.settings.common);
    cli::validateSimplify(a.flags);
    return cli::runStage("simplify", a.flags.settings, a.quiet, runSimplify);
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Args>("simplify", argc, argv, parseArgs, run); }

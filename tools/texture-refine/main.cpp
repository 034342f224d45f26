// texture-refine: parameterized multiresolution glTF in, same + texture hierarchy out (MIP-style
// resolutions and rank-refined layouts, thesis chapter 4). `pack` picks from it per LOD.
// Parses the flags (common/stage_flags.h) into TextureRefineSettings, validates them and runs the
// stage (lodbake/stages/texture_refine.h).
#include "common/stage_flags.h"

using namespace lodbake;

namespace {

struct Args {
    cli::TextureRefineFlags flags;
    bool quiet = false;
};

Args parseArgs(int argc, char** argv, bool& proceed) {
    Args a;
    cli::ArgParser p("texture-refine", "-i INPUT.uv.glb -o OUTPUT.tex.glb [options]");
    p.addCommon(a.flags.settings.common, a.quiet);
    cli::addTextureRefineFlags(p, a.flags);
    proceed = p.parse(argc, argv);
    return a;
}

int run(Args& a) {
    cli::validateTextureRefine(a.flags);
    cli::checkPaths(a.flags.settings.common);
    return cli::runStage("texture-refine", a.flags.settings, a.quiet, runTextureRefine);
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Args>("texture-refine", argc, argv, parseArgs, run); }

// The simplify stage: any glTF in, multiresolution glTF out (half-edge collapse with region
// hierarchy, lodbake/simplify/simplify.h).
#pragma once

#include <string>

#include "lodbake/simplify/simplify.h"
#include "lodbake/stages/stage.h"

namespace lodbake {

struct SimplifySettings {
    StageCommon common;
    // The algorithm's options; `levels` must be set (at least one target). threads and progress
    // are taken from `common`.
    SimplifyOptions simplify;
    // Rigged inputs: the poses sampled from the asset's rig into simplify.posed (the rest pose and
    // times of each animation); perAnimation = 0 measures in the bind pose only.
    PoseSampleOptions poses;
    // Why these levels (the report's levelsChosen): given by flags, or the default.
    std::string levelsChosen;
};

// Reads common.input, simplifies it, writes common.output with LODBAKE_multires and the report.
// \throw Impossible when the scene has no triangles; the errors of reading and writing.
StageResult runSimplify(const SimplifySettings& settings);

}  // namespace lodbake

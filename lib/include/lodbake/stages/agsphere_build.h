// The agsphere-build stage: any glTF in, multiresolution glTF out (M-AGSphere,
// lodbake/agsphere/agsphere.h), in the same format as the simplify stage.
#pragma once

#include "lodbake/agsphere/agsphere.h"
#include "lodbake/stages/stage.h"

namespace lodbake {

struct AgsphereBuildSettings {
    StageCommon common;
    // The algorithm's options; `levels` must be set (at least one target). threads and progress
    // are taken from `common`.
    AgsphereOptions agsphere;
};

// Reads common.input, builds the levels, writes common.output with LODBAKE_multires and the report.
// \throw Impossible when the scene has no triangles; the errors of reading and writing.
StageResult runAgsphereBuild(const AgsphereBuildSettings& settings);

}  // namespace lodbake

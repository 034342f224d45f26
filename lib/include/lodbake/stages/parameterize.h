// The parameterize stage: multiresolution glTF in, the same plus the chart layout, atlas UVs for
// every level and one baked base-colour texture valid for every level out (thesis 3.3).
// Pipeline: parameterize (charts, per-chart flattening, atlas) -> bake -> apply the atlas ->
// check every level's UVs -> texture deviation of the coarsest level -> report -> write.
#pragma once

#include "lodbake/param/parameterize.h"
#include "lodbake/stages/stage.h"

namespace lodbake {

struct ParameterizeSettings {
    StageCommon common;
    // The algorithm's options (textureSize is also the baked atlas side). threads and progress
    // are taken from `common`.
    ParameterizeOptions parameterize;
    // Bake the atlas image (the original base colour at the atlas UVs) into the output. texture-refine
    // and pack never read it (they bake from the original images): the lodbake chain skips it
    // unless the .uv.glb is kept. Without it the atlas material has factors only.
    bool bakeImage = true;
};

// Folds that survive every fallback (see parameterize) are warnings, not errors: the output is
// written. \throw Impossible when the input has no LODBAKE_multires extension or the charts do not
//        fit the texture; the errors of reading, decoding images and writing.
StageResult runParameterize(const ParameterizeSettings& settings);

}  // namespace lodbake

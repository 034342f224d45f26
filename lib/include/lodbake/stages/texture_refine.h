// The texture-refine stage: parameterized multiresolution glTF in, the same plus the texture
// hierarchy (MIP-style resolutions and rank-refined layouts, thesis chapter 4) out.
#pragma once

#include "lodbake/stages/stage.h"
#include "lodbake/texture_hierarchy/refine.h"

namespace lodbake {

struct TextureRefineSettings {
    StageCommon common;
    RefineOptions refine;  // threads and progress are taken from `common`
};

// \throw Impossible when the input has no LODBAKE_multires extension or no chart layout; the
//        errors of reading, decoding images and writing.
StageResult runTextureRefine(const TextureRefineSettings& settings);

}  // namespace lodbake

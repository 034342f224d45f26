// The pack stage: parameterized multiresolution glTF in, the final glTF LOD chain out (MSFT_lod,
// one mesh / one material / one draw call per level, atlases sized for each level's screen size).
#pragma once

#include "lodbake/lod/lod_chain.h"
#include "lodbake/stages/pack_write.h"
#include "lodbake/stages/stage.h"

namespace lodbake {

struct PackSettings {
    StageCommon common;
    PackOptions pack;  // threads and progress are taken from `common`
    PackWriteOptions write = defaultPackWrite();
    // The image format as the report names it ("png", "jpeg" or the "jpg" alias as given); empty
    // = imageFormatName(pack.imageFormat).
    std::string imageFormatName;

    static PackWriteOptions defaultPackWrite() {
        PackWriteOptions w;
        w.chain.generator = "lodbake pack 0.1.0";
        return w;
    }
};

// "png" or "jpeg".
const char* imageFormatName(ImageFormat format);
// "baked" or "original".
const char* lod0Name(Lod0 mode);
// "auto", "always" or "never".
const char* normalMapsName(NormalMaps mode);

// \throw Impossible when the input has no LODBAKE_multires extension; the errors of reading,
//        decoding images, packing and writing.
StageResult runPack(const PackSettings& settings);

}  // namespace lodbake

// KTX2 textures (KHR_texture_basisu) through the Basis Universal encoder executable, `basisu`,
// as gltfpack does: the image goes to the encoder through files in a private temporary folder
// (removed afterwards), never through a shell.
#pragma once

#include <string>

#include "lodbake/core/mesh.h"

namespace lodbake {

enum class Ktx2Codec {
    Etc1s,  // small, lossy in colour: base colour and emissive
    Uastc,  // about 8 bits per texel before Zstandard, close to the source: normal and ORM maps
};

struct Ktx2Options {
    std::string encoder;           // path of the basisu executable (findBasisu)
    Ktx2Codec codec = Ktx2Codec::Etc1s;
    bool srgb = true;              // colour in sRGB; false = linear data (metrics, mip filtering, KTX2 transfer)
    bool normalMap = false;        // basisu -normal_map (linear, no selector RDO)
    int etc1sQuality = 128;        // basisu -q, 1..255
    int uastcLevel = 2;            // basisu -uastc_level, 0..4
    bool mipmaps = true;           // the full mip chain (the chain's sampler minifies with mipmaps)
};

// The encoder: $BASISU_PATH when set, else the first `basisu` on $PATH; "" when neither exists.
std::string findBasisu();

// The KTX2 file of an encoded PNG or JPEG image (mimeType "image/ktx2", same size and name).
// Single-threaded encoder runs: the bytes do not depend on the machine's core count.
// \throw IOError (encoder missing, failed, or wrote nothing).
Image encodeKtx2(const Image& source, const Ktx2Options& options);

}  // namespace lodbake

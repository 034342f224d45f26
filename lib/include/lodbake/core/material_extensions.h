// The ratified KHR_materials_* extensions a Material carries beside glTF's core channels, as the
// glTF specification defines them (factors, textures with their channel, defaults). A struct per
// extension; `present` = the material has the extension (its values are then meaningful, else
// they are the extension's defaults and the material behaves as without it).
//
// Texture channels (glTF): clearcoat R, clearcoat roughness G, clearcoat normal RGB; sheen colour
// RGB (sRGB), sheen roughness A; transmission R; volume thickness G; specular A, specular colour
// RGB (sRGB); iridescence R, iridescence thickness G; anisotropy RG = direction, B = strength;
// diffuse transmission A, diffuse transmission colour RGB (sRGB).
#pragma once

#include <limits>
#include <vector>

#include "lodbake/core/math.h"

namespace lodbake {

// KHR_texture_transform on one texture reference; identity when !present.
struct TextureTransform {
    bool present = false;
    Vec2 offset{0, 0};
    double rotation = 0;  // radians
    Vec2 scale{1, 1};
    int texCoord = -1;    // overrides TextureRef::texCoord when >= 0
};

struct TextureRef {
    int texture = -1;  // index into Asset::textures; -1 = none
    int texCoord = 0;  // which TEXCOORD_n
    double scale = 1;  // normalTexture.scale / occlusionTexture.strength
    TextureTransform transform;
};

struct ClearcoatExtension {  // KHR_materials_clearcoat
    bool present = false;
    double factor = 0;
    TextureRef texture;              // R
    double roughnessFactor = 0;
    TextureRef roughnessTexture;     // G
    TextureRef normalTexture;        // tangent-space normal map of the coat (scale = its normal scale)
};

struct SheenExtension {  // KHR_materials_sheen
    bool present = false;
    Vec3 colorFactor{0, 0, 0};       // linear
    TextureRef colorTexture;         // RGB, sRGB
    double roughnessFactor = 0;
    TextureRef roughnessTexture;     // A
};

struct TransmissionExtension {  // KHR_materials_transmission
    bool present = false;
    double factor = 0;
    TextureRef texture;              // R
};

struct VolumeExtension {  // KHR_materials_volume
    bool present = false;
    double thicknessFactor = 0;      // mesh-space units
    TextureRef thicknessTexture;     // G
    double attenuationDistance = std::numeric_limits<double>::infinity();  // mesh-space units; inf = no attenuation
    Vec3 attenuationColor{1, 1, 1};  // linear
};

struct SpecularExtension {  // KHR_materials_specular
    bool present = false;
    double factor = 1;
    TextureRef texture;              // A
    Vec3 colorFactor{1, 1, 1};       // linear, may exceed 1
    TextureRef colorTexture;         // RGB, sRGB
};

struct IorExtension {  // KHR_materials_ior
    bool present = false;
    double ior = 1.5;
};

struct IridescenceExtension {  // KHR_materials_iridescence
    bool present = false;
    double factor = 0;
    TextureRef texture;              // R
    double ior = 1.3;
    double thicknessMinimum = 100;   // nanometres
    double thicknessMaximum = 400;   // nanometres; the thickness where there is no thickness texture
    TextureRef thicknessTexture;     // G: thickness = mix(minimum, maximum, G)
};

struct AnisotropyExtension {  // KHR_materials_anisotropy
    bool present = false;
    double strength = 0;
    double rotation = 0;             // radians, counter-clockwise from the tangent
    TextureRef texture;              // RG = direction in tangent space ([-1,1] encoded), B = strength
};

struct DispersionExtension {  // KHR_materials_dispersion
    bool present = false;
    double dispersion = 0;           // 20 / Abbe number
};

struct DiffuseTransmissionExtension {  // KHR_materials_diffuse_transmission
    bool present = false;
    double factor = 0;
    TextureRef texture;              // A
    Vec3 colorFactor{1, 1, 1};       // linear
    TextureRef colorTexture;         // RGB, sRGB
};

struct MaterialExtensions {
    ClearcoatExtension clearcoat;
    SheenExtension sheen;
    TransmissionExtension transmission;
    VolumeExtension volume;
    SpecularExtension specular;
    IorExtension ior;
    IridescenceExtension iridescence;
    AnisotropyExtension anisotropy;
    DispersionExtension dispersion;
    DiffuseTransmissionExtension diffuseTransmission;
};

// Every texture reference of the extensions (also those without a texture), in a fixed order.
inline std::vector<const TextureRef*> textureRefs(const MaterialExtensions& e) {
    return {&e.clearcoat.texture,       &e.clearcoat.roughnessTexture, &e.clearcoat.normalTexture,
            &e.sheen.colorTexture,      &e.sheen.roughnessTexture,     &e.transmission.texture,
            &e.volume.thicknessTexture, &e.specular.texture,           &e.specular.colorTexture,
            &e.iridescence.texture,     &e.iridescence.thicknessTexture, &e.anisotropy.texture,
            &e.diffuseTransmission.texture, &e.diffuseTransmission.colorTexture};
}

}  // namespace lodbake

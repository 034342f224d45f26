// The material properties glTF cannot vary per texel (DESIGN.md "Bake and gap fill"): one value
// per primitive. The chain's levels share one set of baked pages; where the input's materials
// disagree on one of these, a level is drawn as several primitives whose materials differ in
// these values only (lodbake/bake/draw_split.h).
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

struct MaterialUniforms {
    AlphaMode alphaMode = AlphaMode::Opaque;
    double alphaCutoff = 0.5;  // MASK only
    bool unlit = false;        // KHR_materials_unlit
    double ior = 1.5;          // KHR_materials_ior
    // KHR_materials_volume: mesh-space units (inf = no attenuation), linear colour.
    double attenuationDistance = std::numeric_limits<double>::infinity();
    Vec3 attenuationColor{1, 1, 1};
    double dispersion = 0;         // KHR_materials_dispersion
    double iridescenceIor = 1.3;   // KHR_materials_iridescence
    // KHR_materials_transmission: whether the primitive transmits at all. Renderers draw a
    // transmissive primitive after the opaque ones and refract only those (three.js, Babylon.js),
    // so the parts that do not transmit must not carry the extension, or nothing shows through.
    bool transmission = false;
};

// The names of the properties on which `a` and `b` differ, in this order: "alphaMode",
// "alphaCutoff" (when both are MASK), "unlit", "ior", "attenuationDistance", "attenuationColor",
// "dispersion", "iridescenceIor", "transmission".
inline std::vector<std::string> uniformDifferences(const MaterialUniforms& a, const MaterialUniforms& b) {
    std::vector<std::string> out;
    if (a.alphaMode != b.alphaMode) out.push_back("alphaMode");
    if (a.alphaMode == AlphaMode::Mask && b.alphaMode == AlphaMode::Mask && a.alphaCutoff != b.alphaCutoff) out.push_back("alphaCutoff");
    if (a.unlit != b.unlit) out.push_back("unlit");
    if (a.ior != b.ior) out.push_back("ior");
    if (a.attenuationDistance != b.attenuationDistance) out.push_back("attenuationDistance");
    const Vec3 &c = a.attenuationColor, &d = b.attenuationColor;
    if (c.x != d.x || c.y != d.y || c.z != d.z) out.push_back("attenuationColor");
    if (a.dispersion != b.dispersion) out.push_back("dispersion");
    if (a.iridescenceIor != b.iridescenceIor) out.push_back("iridescenceIor");
    if (a.transmission != b.transmission) out.push_back("transmission");
    return out;
}

inline bool operator==(const MaterialUniforms& a, const MaterialUniforms& b) {
    return a.alphaCutoff == b.alphaCutoff && uniformDifferences(a, b).empty();
}

// Sets a material's per-primitive properties to `u`: alpha mode and cutoff, unlit, and the
// properties of the extensions `ext` carries (an absent extension stays absent). A part that does
// not transmit drops KHR_materials_transmission, and with it the volume and dispersion only
// transmission shows (a volume stays where diffuse transmission shows it).
inline void applyUniforms(const MaterialUniforms& u, AlphaMode& alphaMode, double& alphaCutoff, bool& unlit, MaterialExtensions& ext) {
    alphaMode = u.alphaMode;
    alphaCutoff = u.alphaCutoff;
    unlit = u.unlit;
    if (ext.ior.present) ext.ior.ior = u.ior;
    if (ext.volume.present) {
        ext.volume.attenuationDistance = u.attenuationDistance;
        ext.volume.attenuationColor = u.attenuationColor;
    }
    if (ext.dispersion.present) ext.dispersion.dispersion = u.dispersion;
    if (ext.iridescence.present) ext.iridescence.ior = u.iridescenceIor;
    if (!u.transmission && ext.transmission.present) {
        ext.transmission.present = false;
        if (!ext.diffuseTransmission.present) ext.volume.present = ext.dispersion.present = false;
    }
}

}  // namespace lodbake

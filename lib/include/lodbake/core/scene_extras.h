// What a glTF scene holds besides its meshes and that lodbake carries from input to output:
// KHR_lights_punctual lights, cameras, the nodes that place them, and the JSON `extras` of the
// root, its `asset` and its scene. No format-library types here (STYLE.md practice 10): extras
// travel as JSON text, which only lib/src/gltf parses and writes.
//
// What holds: every placement names a light and/or a camera of this struct; its `world` is the
// node's world matrix in the flattened scene at rest (a node below an animated node keeps its rest
// transform: the reader warns). Writers (intermediates and the MSFT_lod chain) put each placement
// in the default scene as a root node with that transform and its name, so reading an output back
// gives the same lights, cameras and placements.
#pragma once

#include <string>
#include <vector>

#include "lodbake/core/math.h"

namespace lodbake {

// One KHR_lights_punctual light. Units as the extension: point and spot in candela, directional
// in lux; angles in radians.
struct SceneLight {
    enum class Type { Directional, Point, Spot };
    std::string name;
    Type type = Type::Point;
    Vec3 color{1, 1, 1};           // linear RGB
    double intensity = 1;
    double range = 0;              // 0 = unset (infinite); point and spot only
    double innerConeAngle = 0;     // spot only
    double outerConeAngle = 0.7853981633974483;  // spot only (pi / 4, the extension's default)
};

// One glTF camera (looks down its node's -Z, +Y up). Distances in the scene's units, yfov in radians.
struct SceneCamera {
    enum class Type { Perspective, Orthographic };
    std::string name;
    Type type = Type::Perspective;
    double aspectRatio = 0;  // perspective; 0 = unset (the viewport's)
    double yfov = 0.8;       // perspective
    double xmag = 1, ymag = 1;  // orthographic
    double znear = 0.01;
    double zfar = 0;         // 0 = unset (an infinite perspective projection); orthographic always sets it
};

// A node that places a light and/or a camera.
struct ScenePlacement {
    std::string name;  // the node's name ("" = none)
    Mat4 world = identity4();
    int light = -1;    // index into SceneExtras::lights; -1 = none
    int camera = -1;   // index into SceneExtras::cameras; -1 = none
};

struct SceneExtras {
    std::vector<SceneLight> lights;
    std::vector<SceneCamera> cameras;
    std::vector<ScenePlacement> placements;  // in the input's depth-first node order
    // JSON text of `extras` of the root, of root.asset and of the default scene; "" = absent.
    std::string rootExtras, assetExtras, sceneExtras;

    bool empty() const {
        return lights.empty() && cameras.empty() && placements.empty() && rootExtras.empty() && assetExtras.empty() &&
               sceneExtras.empty();
    }
};

}  // namespace lodbake

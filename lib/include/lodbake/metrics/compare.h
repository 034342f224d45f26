// compareAssets: everything `compare` reports about two assets (DESIGN.md "How we judge output"):
// budgets (triangles, vertices, materials, draw calls, texels), geometric distance (distance.h)
// and image distance of unlit base colour, shaded shape and lit PBR renders (render.h,
// image_metrics.h).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/metrics/distance.h"
#include "lodbake/metrics/image_metrics.h"
#include "lodbake/metrics/render.h"

namespace lodbake {

struct ModelCounts {
    uint64_t triangles = 0;
    uint64_t vertices = 0;   // distinct wedges (glTF vertices) referenced by the triangles
    uint64_t positions = 0;  // distinct welded positions referenced by the triangles
    uint64_t materials = 0;  // distinct materials used by the triangles (the default material counts)
    uint64_t drawCalls = 0;  // one primitive per used material (how lodbake and gltfpack write)
    uint64_t texels = 0;     // sum of width*height of the distinct images the used materials reference
};

// Counts of `mesh` with `asset`'s materials and images.
ModelCounts countModel(const Asset& asset, const TriMesh& mesh);

struct CompareOptions {
    bool geometry = true;           // compute the geometric distance
    DistanceOptions distance;
    bool images = true;             // render and compare
    int views = 16;                 // cameras on a Fibonacci sphere around A's bounding sphere
                                    // (centre: A's box centre; radius: farthest vertex from it)
    int resolution = 256;           // square renders, pixels
    // Radians (30 degrees): a viewer's camera (three.js as scripts/render_three.py sets it up,
    // <model-viewer>); a wider angle puts the camera close enough that near surfaces are seen
    // at grazing angles no viewer shows, and their texture minification decides the figures.
    double fovY = 0.5235987755982988;
    int threads = 0;                // 0 = all cores; never changes the result
    bool keepRenders = false;       // keep the renders in the result (for a contact sheet)
};

// The render modes compared, in the order of CompareResult's renders and contact-sheet columns.
constexpr RenderMode kCompareModes[3] = {RenderMode::BaseColor, RenderMode::Shaded, RenderMode::Pbr};

struct CompareResult {
    ModelCounts a, b;
    GeometricDistance distance;      // valid when options.geometry
    ImageMetrics baseColor, shaded, pbr;  // valid when options.images
    std::vector<ImageMetrics> baseColorPerView, shadedPerView, pbrPerView;
    // When keepRenders: per view, one render per mode in kCompareModes order.
    std::vector<std::array<Rendering, 3>> rendersA, rendersB;
    std::vector<std::string> warnings;
};

// \pre meshA and meshB index into assetA's and assetB's materials respectively.
// \throw Impossible when a mesh has no non-degenerate triangle (geometry on).
CompareResult compareAssets(const Asset& assetA, const TriMesh& meshA, const Asset& assetB,
                            const TriMesh& meshB, const CompareOptions& options = {});

struct ContactSheetOptions {
    double diffGain = 4;  // |A-B| is multiplied by this
};

// Writes a PNG contact sheet of renders kept by compareAssets (keepRenders): one row per view;
// columns A, B, |A-B| x gain for base colour, then the same for shaded, then for pbr. Written
// atomically.
// \throw IOError when the file cannot be written; InvalidInput when there are no renders.
void writeContactSheet(const std::string& path, const CompareResult& result, const ContactSheetOptions& options = {});

}  // namespace lodbake

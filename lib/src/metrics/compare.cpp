// compareAssets (compare.h): counts, geometric distance, then renders of both assets from the
// same views in every mode (kCompareModes) and their image metrics. Views run in parallel; every view writes its
// own slot and the slots are pooled in view order, so the figures never depend on `threads`.
#include "lodbake/metrics/compare.h"

#include <algorithm>
#include <set>

#include "lodbake/core/parallel.h"

namespace lodbake {

ModelCounts countModel(const Asset& asset, const TriMesh& mesh) {
    ModelCounts c;
    c.triangles = mesh.triangles.size();
    std::vector<uint8_t> usedPos(mesh.positions.size(), 0), usedWedge(mesh.wedges.size(), 0);
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            usedPos[mesh.triangles[t][k]] = 1;
            if (t < mesh.cornerWedges.size() && mesh.cornerWedges[t][k] < usedWedge.size())
                usedWedge[mesh.cornerWedges[t][k]] = 1;
        }
    for (uint8_t u : usedPos) c.positions += u;
    for (uint8_t u : usedWedge) c.vertices += u;
    if (mesh.cornerWedges.empty()) c.vertices = c.positions;
    std::set<int32_t> materials(mesh.triangleMaterial.begin(), mesh.triangleMaterial.end());
    if (mesh.triangleMaterial.empty() && !mesh.triangles.empty()) materials.insert(-1);
    c.materials = materials.size();
    c.drawCalls = materials.size();
    std::set<int> images;
    for (int32_t m : materials) {
        if (m < 0 || static_cast<size_t>(m) >= asset.materials.size()) continue;
        const Material& mat = asset.materials[m];
        for (const TextureRef* r : {&mat.baseColor, &mat.metallicRoughness, &mat.normal, &mat.occlusion, &mat.emissive}) {
            if (r->texture < 0 || static_cast<size_t>(r->texture) >= asset.textures.size()) continue;
            int i = asset.textures[r->texture].image;
            if (i >= 0 && static_cast<size_t>(i) < asset.images.size()) images.insert(i);
        }
    }
    for (int i : images) c.texels += static_cast<uint64_t>(asset.images[i].width) * asset.images[i].height;
    return c;
}

CompareResult compareAssets(const Asset& assetA, const TriMesh& meshA, const Asset& assetB, const TriMesh& meshB,
                            const CompareOptions& options) {
    CompareResult r;
    r.a = countModel(assetA, meshA);
    r.b = countModel(assetB, meshB);

    if (options.geometry) {
        DistanceOptions d = options.distance;
        if (d.threads == 0) d.threads = options.threads;
        r.distance = surfaceDistance(meshA, meshB, d);
    }

    if (options.images && options.views > 0) {
        RenderScene sceneA = prepareRenderScene(assetA, meshA);
        RenderScene sceneB = prepareRenderScene(assetB, meshB);
        for (auto& w : sceneA.warnings) r.warnings.push_back("A: " + w);
        for (auto& w : sceneB.warnings) r.warnings.push_back("B: " + w);
        Box3 box = bounds(meshA);
        Vec3 center = box.empty() ? Vec3{} : (box.min + box.max) * 0.5;
        // Bounding sphere: box centre, radius to the farthest referenced vertex (tighter than the box).
        double radius = 0;
        for (const Tri& t : meshA.triangles)
            for (uint32_t v : t) radius = std::max(radius, length(meshA.positions[v] - center));
        std::vector<Camera> cams = sphereViews(options.views, center, radius, options.fovY);
        constexpr size_t kModes = sizeof(kCompareModes) / sizeof(kCompareModes[0]);
        const size_t jobs = cams.size() * kModes;
        std::vector<ImageMetrics> metrics(jobs);
        std::vector<std::array<Rendering, kModes>> keepA, keepB;
        if (options.keepRenders) {
            keepA.resize(cams.size());
            keepB.resize(cams.size());
        }
        parallelFor(jobs, options.threads, [&](size_t j) {
            const size_t view = j / kModes, mode = j % kModes;
            RenderOptions ro;
            ro.width = ro.height = options.resolution;
            ro.mode = kCompareModes[mode];
            Rendering ia = render(sceneA, cams[view], ro);
            Rendering ib = render(sceneB, cams[view], ro);
            metrics[j] = compareImages(ia, ib);
            if (options.keepRenders) {
                keepA[view][mode] = std::move(ia);
                keepB[view][mode] = std::move(ib);
            }
        });
        ImageMetrics* pooled[kModes] = {&r.baseColor, &r.shaded, &r.pbr};
        std::vector<ImageMetrics>* perView[kModes] = {&r.baseColorPerView, &r.shadedPerView, &r.pbrPerView};
        for (size_t j = 0; j < jobs; ++j) {
            accumulate(*pooled[j % kModes], metrics[j]);
            perView[j % kModes]->push_back(metrics[j]);
        }
        r.rendersA = std::move(keepA);
        r.rendersB = std::move(keepB);
    }
    return r;
}

}  // namespace lodbake

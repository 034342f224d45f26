// A parameterized asset built in code for the unit tests of the stages after parameterize.
#pragma once

#include "lodbake/atlas/atlas_apply.h"
#include "lodbake/bake/bake.h"
#include "lodbake/core/multires.h"
#include "lodbake/param/parameterize.h"
#include "lodbake/simplify/simplify.h"
#include "synthetic_meshes.h"

namespace lodbake::test {

struct Parameterized {
    Asset asset;
    Multires mr;
};

// hemisphere(4) in one orange material -> simplify (0.5, 0.1, 0.02) -> parameterize (256) ->
// applyAtlas with a 64 x 64 base colour bake; built once.
inline const Parameterized& hemisphereAsset() {
    static const Parameterized p = [] {
        Parameterized r;
        r.asset.mesh = hemisphere(4);
        r.asset.materials.push_back(Material{});
        r.asset.materials[0].baseColorFactor = {0.8, 0.4, 0.2, 1};
        SimplifyOptions so;
        for (double ratio : {0.5, 0.1, 0.02}) so.levels.push_back({ratio, 0, 0});
        r.mr = simplify(r.asset.mesh, so).multires;
        ParameterizeOptions po;
        po.textureSize = 256;
        ParameterizeResult pr = parameterize(r.asset.mesh, r.mr, po);
        BakeOptions bo;
        bo.size = 64;
        applyAtlas(r.asset, r.mr, pr, bakeBaseColor(r.asset, pr.cornerUV, bo).image);
        return r;
    }();
    return p;
}

}  // namespace lodbake::test

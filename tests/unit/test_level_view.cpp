// A level that shows the original's surface (lib/src/lod/level_view.h): the original's triangles
// of the same faces, unmoved, with the original corners' normals, through wedges of its own.
#include <gtest/gtest.h>

#include "lod/level_view.h"

using namespace lodbake;
using namespace lodbake::lod_detail;

namespace {

// A unit square of two triangles, four wedges with +z normals:
//   3 --- 2
//   |  /  |
//   0 --- 1
TriMesh square() {
    TriMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.cornerWedges = {{0, 1, 2}, {0, 2, 3}};
    m.wedges.vertex = {0, 1, 2, 3};
    m.wedges.normal.assign(4, Vec3{0, 0, 1});
    return m;
}

// The square as a level whose corners use copies of the wedges (ids 4..7), as simplify's levels do.
LevelView keptLevel(TriMesh& m) {
    for (uint32_t w = 0; w < 4; ++w) {
        m.wedges.vertex.push_back(w);
        m.wedges.normal.push_back(m.wedges.normal[w]);
    }
    LevelView lv;
    lv.triangles = m.triangles;
    lv.cornerWedges = {{4, 5, 6}, {4, 6, 7}};
    lv.faces = {0, 1};
    return lv;
}

}  // namespace

TEST(LevelView, AKeptLevelThroughWedgeCopiesShowsTheOriginalSurface) {
    TriMesh m = square();
    const LevelView lv = keptLevel(m);
    EXPECT_TRUE(showsOriginalSurface(m, lv));
}

TEST(LevelView, MovedFewerOrReshadedLevelsDoNot) {
    TriMesh m = square();
    LevelView moved = keptLevel(m);
    moved.positions = m.positions;
    moved.positions[2].z = 0.1;
    EXPECT_FALSE(showsOriginalSurface(m, moved));

    LevelView fewer = keptLevel(m);
    fewer.triangles.pop_back();
    fewer.cornerWedges.pop_back();
    fewer.faces.pop_back();
    EXPECT_FALSE(showsOriginalSurface(m, fewer));

    LevelView reshaded = keptLevel(m);
    m.wedges.normal[6] = normalize(Vec3{0, 1, 1});  // the copy of corner 2 bends
    EXPECT_FALSE(showsOriginalSurface(m, reshaded));

    // Without normals viewers draw the original flat; the level's own normals need the map.
    TriMesh flat = square();
    const LevelView kept = keptLevel(flat);
    flat.wedges.normal.clear();
    EXPECT_FALSE(showsOriginalSurface(flat, kept));
}

// Where pack's time went: wall and process CPU seconds of the chain's steps, for the report.
// Never part of any output file, and filled only when PackOptions::profile points at one.
#pragma once

#include <vector>

namespace lodbake {

struct PackLevelProfile {
    // Layout UVs (and own charts), page search, level mesh (with tangents), bake, material (the
    // baked channels encoded): wall and process CPU seconds.
    struct Steps {
        double uvs = 0, page = 0, mesh = 0, bake = 0, material = 0;
    };
    Steps wall, cpu;
    double bakeSeconds = 0;          // the page bake itself (BakeResult::seconds; 0 for a level that copies the previous one's)
    double placementSeconds = 0;     // vertex placement and the measures that decide it (projected coarse levels)
    double placeSeconds = 0;         // ... placement alone
    double rankChoiceSeconds = 0, rankChoiceCpuSeconds = 0;  // the layout chosen by the bake (probe, candidates' pages and bakes)
};

struct PackProfile {
    double seconds = 0;                                // the whole of packLodChain, wall
    double measureSeconds = 0, measureCpuSeconds = 0;  // of seconds: the levels' measured deviation (wall, CPU)
    std::vector<PackLevelProfile> levels;              // per level, LOD0 first
};

}  // namespace lodbake

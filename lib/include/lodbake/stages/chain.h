// The whole chain in one call: simplify -> parameterize -> [texture-refine] -> pack, the same
// stages the separate tools run, in one process. Each stage's output reaches the next as the .glb
// bytes the tool would have written (StageCommon::inputBytes / outputBytes): the files store
// float32 attributes and the LODBAKE_multires extension, so passing exactly those bytes is what
// makes the final chain byte-identical to running the four tools one after another. Nothing is
// written between the stages unless keepIntermediates names a folder.
#pragma once

#include <functional>
#include <string>

#include "lodbake/stages/pack.h"
#include "lodbake/stages/parameterize.h"
#include "lodbake/stages/simplify.h"
#include "lodbake/stages/stage.h"
#include "lodbake/stages/texture_refine.h"

namespace lodbake {

struct ChainSettings {
    // input = the asset, output = the LOD chain (pack's output), report = the chain's report;
    // verbose, threads and warning apply to every stage. common.progress is not used (see
    // `progress` below).
    StageCommon common;
    // Each stage's own options; their `common` members are filled in by runChain.
    SimplifySettings simplify;
    ParameterizeSettings parameterize;
    TextureRefineSettings textureRefine;
    PackSettings pack;
    bool runTextureRefine = true;  // false: pack reads parameterize's output
    // Folder for the intermediates as the tools name them: <stem>.mr.glb, .uv.glb, .tex.glb (stem =
    // the input's file name without extension). Empty: they stay in memory.
    std::string keepIntermediates;
    // HTML report to write (lodbake --html): every level of the chain measured against the input by
    // the compare stage, shown beside pack's figures with renders and atlas pages. Empty: none.
    // \pre a single-file chain (pack's split off).
    std::string html;
    // Progress of the running stage ("simplify", ...), fraction in [0, 1]; may be empty.
    std::function<bool(const std::string& stage, double fraction)> progress;
};

// The chain's report: {"tool": "lodbake", "input", "output", "stages": [each stage's own report,
// in order], "intermediates", "warnings", "time": {"total"}}, and with `html` "compare": [the
// compare stage's report of each level against the input] and time.review; statistics: each
// stage's -v text under a "STAGE:" line.
StageResult runChain(const ChainSettings& settings);

}  // namespace lodbake

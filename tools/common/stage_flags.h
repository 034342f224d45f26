// The flags of each chain stage, defined once: the separate tools (simplify, parameterize,
// texture-refine, pack) and the one-command `lodbake` add the same flags with the same defaults,
// help texts and checks. Each stage has a Flags struct (its settings plus the values that are
// only turned into settings by validation), an add function and a validate function; the paths
// (-i/-o/--report, cli::checkPaths) are the caller's, because the tools check them at different
// points of their validation.
//
// One definition per source file (simplify_flags.cpp, ...), so a tool links only its own stage.
#pragma once

#include <string>
#include <vector>

#include "common/cli.h"
#include "lodbake/stages/pack.h"
#include "lodbake/stages/parameterize.h"
#include "lodbake/stages/simplify.h"
#include "lodbake/stages/texture_refine.h"

namespace lodbake::cli {

struct SimplifyFlags {
    SimplifySettings settings;
    std::vector<double> ratios, triangles, maxErrors;  // the level flags, turned into settings.simplify.levels
};
// --ratio, --triangles, --max-error, --max-region-cone, --max-part-removal, --gross-error, --two-sided-cost,
// --no-visual-weight, --max-influence-change, --pose-samples.
void addSimplifyFlags(ArgParser& parser, SimplifyFlags& flags);
// Checks the level flags and sets settings.simplify.levels. \throw UsageError.
void validateSimplify(SimplifyFlags& flags);

struct ParameterizeFlags {
    ParameterizeSettings settings;
    int maxCharts = 0;  // --max-charts as given (checked >= 0 before it becomes charts.maxCharts)
};
// --size, --alpha, --beta, --max-charts, --iterations, --no-level-islands, --no-crossing-islands,
// --allow-level-folds (deprecated, no effect).
void addParameterizeFlags(ArgParser& parser, ParameterizeFlags& flags);
// \throw UsageError.
void validateParameterize(ParameterizeFlags& flags);
// The paragraph parameterize's --help ends with (level islands, exit 4 on folded levels).
std::string parameterizeExitCodes();

struct TextureRefineFlags {
    TextureRefineSettings settings;
    // Prepended to the names of the flags another chain stage also has (--size, --alpha, --beta,
    // --iterations, --split): "" for the texture-refine tool, "refine-" for lodbake.
    std::string clashPrefix;
};
// --size, --sizes, --min-refined-size, --min-std-dev, --max-extra-cuts,
// --keep-level-triangles-whole, --ranks, --split, --alpha, --beta, --iterations.
void addTextureRefineFlags(ArgParser& parser, TextureRefineFlags& flags, const std::string& clashPrefix = "");
// \throw UsageError.
void validateTextureRefine(const TextureRefineFlags& flags);

struct PackFlags {
    PackSettings settings;
    bool ktx2 = false;  // --image-format ktx2: validatePack looks the encoder up
};
// --pixel-error ... --external-images (docs/pack.md).
void addPackFlags(ArgParser& parser, PackFlags& flags);
// Also finds the KTX2 encoder for --image-format ktx2. \throw UsageError.
void validatePack(PackFlags& flags);

}  // namespace lodbake::cli

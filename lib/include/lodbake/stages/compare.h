// The compare stage: how far B (usually a LOD) is from A (usually the original): budgets,
// geometric distance and image distance, checked against optional tolerances.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lodbake/metrics/compare.h"
#include "lodbake/metrics/html_report.h"
#include "lodbake/stages/stage.h"

namespace lodbake {

// Limits the comparison must respect; an unset limit is not checked.
struct CompareTolerances {
    std::optional<double> maxHausdorff, maxRms;  // relative to A's bounding-box diagonal
    std::optional<double> minPsnr, minShadedPsnr, minIou, minSsim;  // dB, dB, [0,1], [0,1]
    std::optional<double> minPbrPsnr;                               // dB
};

// Both models posed by one of their animations before they are compared (lodbake/core/pose.h).
struct ComparePose {
    int animation = -1;  // index into the animations; -1 = no posing (the flattened bind pose)
    enum class At { Seconds, Start, Middle, End } at = At::Start;
    double seconds = 0;  // the time when at == Seconds; else the first / middle / last key time of A's animation
};

struct CompareSettings {
    std::string a, b;          // the two glTF files
    int lodA = 0, lodB = 0;    // level compared: LODBAKE_multires level, or MSFT_lod level; 0 = original / LOD0
    CompareOptions compare;    // threads and keepRenders are set from `threads` and `sheet`
    CompareTolerances tolerances;
    bool json = false;         // statistics = the JSON report instead of the table
    std::string report;        // JSON report to write; empty = none
    std::string sheet;         // contact sheet PNG to write; empty = none
    std::string html;          // HTML report to write (metrics/html_report.h); empty = none
    bool pictures = false;     // fill CompareStageResult::views and ::pages even without `html`
    int verbose = 0;           // > 0: per-view image metrics in the table and the report
    int threads = 0;           // 0 = all cores; never changes the result
    ComparePose pose;
};

struct CompareStageResult : StageResult {
    // StageResult::statistics holds what the tool prints on stdout (the table, or the JSON report).
    std::vector<std::string> exceeded;  // one line per tolerance that does not hold
    // With `html` or `pictures`: the HTML report's pictures (metrics/review_images.h): per shown
    // view a strip A | B | |A-B| of the lit (pbr) renders, and thumbnails of B's texture pages.
    std::vector<Image> views, pages;
};

// The image figures both HTML reports show (compare's and lodbake's): PSNR and SSIM of each render
// mode and the silhouette IoU of the lit renders, each a column and its JSON pointer under `base`
// (where a compare report sits in the report the page shows; "" = the report itself).
std::vector<std::pair<HtmlColumn, std::string>> compareImageFigures(const std::string& base);

// \throw Impossible when a --lod level or the --animation is not present in A or a mesh has no
//        non-degenerate triangle;
//        the errors of reading and writing.
CompareStageResult runCompare(const CompareSettings& settings);

}  // namespace lodbake

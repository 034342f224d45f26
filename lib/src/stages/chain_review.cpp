// reviewChain (chain_review.h): one run of the compare stage per level of the chain, then the page's
// layout: pack's figures of the level and compare's image figures in one row per level, compare's
// pictures below. The page reads every figure from the report by pointer (metrics/html_report.h).
#include "chain_review.h"

#include <filesystem>

#include "lodbake/stages/compare.h"

namespace lodbake {
namespace {

// Pack's figures of a level shown on the page: (column, key under the level's object).
const std::pair<HtmlColumn, const char*> kPackFigures[] = {
    {{"", "triangles"}, "/triangles"},
    {{"", "draw calls"}, "/drawCalls"},
    {{"", "texels"}, "/texels"},
    {{"", "bytes"}, "/bytes"},
    {{"measured deviation", "Hausdorff"}, "/deviation/hausdorff"},
    {{"measured deviation", "/ diagonal"}, "/deviation/relHausdorff"},
    {{"", "switch distance"}, "/switchDistance"},
};

HtmlPage layout(const ChainSettings& s, const nlohmann::json& report, std::vector<CompareStageResult>& measured) {
    namespace fs = std::filesystem;
    HtmlPage page;
    page.title = "lodbake: " + fs::path(s.common.input).filename().string() + " \u2192 " + fs::path(s.common.output).filename().string();
    page.facts = {{"input", "/input"},
                  {"output", "/output"},
                  {"levels chosen", "/stages/0/levelsChosen"},
                  {"original triangles", "/compare/0/counts/a/triangles"},
                  {"original bytes", "/compare/0/counts/a/fileBytes"},
                  {"views measured", "/compare/0/images/views"},
                  {"time, seconds", "/time/total"}};
    page.warningLists = {"/warnings"};
    for (size_t k = 0; k < measured.size(); ++k) page.warningLists.push_back("/compare/" + std::to_string(k) + "/warnings");
    page.viewsCaption = "Each view: the original | this level | |difference| x 4, lit (pbr) renders as compare draws them.";
    const std::string pack = "/stages/" + std::to_string(report["stages"].size() - 1) + "/levels/";
    for (const auto& figure : kPackFigures) page.columns.push_back(figure.first);
    for (const auto& figure : compareImageFigures("")) page.columns.push_back(figure.first);
    for (size_t k = 0; k < measured.size(); ++k) {
        HtmlLevel level;
        level.title = "LOD " + std::to_string(k);
        for (const auto& figure : kPackFigures) level.pointers.push_back(pack + std::to_string(k) + figure.second);
        for (const auto& figure : compareImageFigures("/compare/" + std::to_string(k))) level.pointers.push_back(figure.second);
        level.views = std::move(measured[k].views);
        level.pages = std::move(measured[k].pages);
        page.levels.push_back(std::move(level));
    }
    return page;
}

}  // namespace

HtmlPage reviewChain(const ChainSettings& s, nlohmann::json& report, const std::function<bool(double)>& progress) {
    const nlohmann::json& packLevels = report["stages"].back()["levels"];
    const size_t levels = packLevels.size();
    std::vector<CompareStageResult> measured;
    nlohmann::json compared = nlohmann::json::array();
    for (size_t k = 0; k < levels; ++k) {
        if (progress) progress(double(k) / double(levels));
        CompareSettings c;
        c.a = s.common.input;
        c.b = s.common.output;
        c.lodB = int(k);
        c.threads = s.common.threads;
        c.pictures = true;
        measured.push_back(runCompare(c));
        compared.push_back(measured.back().report);
    }
    if (progress) progress(1);
    report["compare"] = std::move(compared);
    return layout(s, report, measured);
}

}  // namespace lodbake

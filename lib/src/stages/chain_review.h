// lodbake --html: the chain just written, level by level, measured against its input by the compare
// stage (each level's figures are those `compare INPUT OUTPUT --lod K` reports), and the HTML page
// that shows them beside pack's own figures of the level.
#pragma once

#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "lodbake/metrics/html_report.h"
#include "lodbake/stages/chain.h"

namespace lodbake {

// Adds "compare" to the chain's report (`report`, as runChain builds it: its last stage is pack's):
// one compare report per level of the chain, in order, and returns the page of `report`.
// `progress` gets the fraction of levels done; may be empty.
// \throw the errors of runCompare (the chain's output is read back).
HtmlPage reviewChain(const ChainSettings& settings, nlohmann::json& report, const std::function<bool(double)>& progress);

}  // namespace lodbake

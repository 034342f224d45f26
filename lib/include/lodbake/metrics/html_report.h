// The HTML report of `compare --html` and `lodbake --html`: one self-contained page (styles inline,
// images as data: URIs, no script, no server) that a reviewer reads in a browser. Warnings on top,
// then one table row of figures per level, then per level its view images and atlas pages.
//
// Every figure on the page is read from the JSON report the tool writes with --report, by JSON
// pointer, so the page and the report cannot disagree: each figure's cell carries its pointer
// (`data-pointer`) and the exact JSON value (`data-value`) beside the rounded text it shows.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "lodbake/core/mesh.h"

namespace lodbake {

// A column of the figures table.
struct HtmlColumn {
    std::string group;  // heading spanning consecutive columns of the same group ("PSNR dB"); empty = none
    std::string label;  // the column's own heading
    int digits = 4;     // significant digits shown of a number that is not an integer
};

// One level (or the one compared model): a row of figures and its pictures.
struct HtmlLevel {
    std::string title;                  // "LOD 2"; also the row's first cell and its section heading
    std::vector<std::string> pointers;  // per column: a JSON pointer into the report; a missing value shows as "n/a"
    std::vector<Image> views;           // encoded images (PNG or JPEG), shown in order; Image::name is the caption
    std::vector<Image> pages;           // atlas page thumbnails; Image::name is the caption
};

struct HtmlPage {
    std::string title;                                       // <title> and the top heading
    std::vector<std::pair<std::string, std::string>> facts;  // (label, JSON pointer): input, output, time, ...
    std::vector<std::string> warningLists;                   // JSON pointers of string arrays shown on top as warnings
    std::string viewsCaption;                                // what a view image shows ("original | level | difference")
    std::vector<HtmlColumn> columns;
    std::vector<HtmlLevel> levels;
};

// The page's HTML text. \pre every level has one pointer per column.
std::string htmlReport(const HtmlPage& page, const nlohmann::json& report);

// Writes htmlReport atomically (a temporary file beside `path`, then renamed): a failed write
// leaves no partial file. \throw IOError when the file cannot be written.
void writeHtmlReport(const std::string& path, const HtmlPage& page, const nlohmann::json& report);

}  // namespace lodbake

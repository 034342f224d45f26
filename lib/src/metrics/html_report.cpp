// The self-contained HTML report (html_report.h): escaping, figures read from the JSON report by
// pointer, images as base64 data: URIs, one inline style sheet. The page's layout, top to bottom:
// title and facts, warnings, the figures table (a row per level), a section per level.
#include "lodbake/metrics/html_report.h"

#include <sstream>

#include "lodbake/gltf/gltf.h"

namespace lodbake {
namespace {

const char* kStyle = R"(
body { font: 14px/1.4 system-ui, sans-serif; margin: 1.5em; color: #222; background: #fff; }
h1 { font-size: 1.4em; margin: 0 0 .4em; } h2 { font-size: 1.15em; margin: 1.4em 0 .4em; } h3 { font-size: 1em; }
dl.facts { display: grid; grid-template-columns: max-content auto; gap: .1em 1em; margin: 0 0 1em; }
dl.facts dt { color: #666; } dl.facts dd { margin: 0; font-family: monospace; }
.warnings { background: #fff4d6; border-left: 4px solid #e0a000; padding: .4em 1em; }
.warnings ul { margin: .2em 0; padding-left: 1.2em; } .ok { color: #2a7a2a; }
table.figures { border-collapse: collapse; font-variant-numeric: tabular-nums; }
table.figures th, table.figures td { border: 1px solid #ccc; padding: .2em .6em; text-align: right; }
table.figures th { background: #f2f2f2; } table.figures tbody th { text-align: left; }
.views, .pages { display: flex; flex-wrap: wrap; gap: .6em; }
figure { margin: 0; } figcaption { color: #666; font-size: .9em; }
img.view { width: 576px; max-width: 100%; height: auto; image-rendering: pixelated; background: #000; }
img.page { max-width: 256px; max-height: 256px; background: repeating-conic-gradient(#ddd 0 25%, #fff 0 50%) 0 0 / 16px 16px; }
)";

std::string escape(const std::string& s) {
    std::string out;
    out.reserve(s.size());
    for (char c : s) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

std::string base64(const std::vector<uint8_t>& bytes) {
    static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t(bytes[i]) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t(bytes[i + 1]) << 8;
        if (i + 2 < bytes.size()) v |= bytes[i + 2];
        out += kDigits[(v >> 18) & 63];
        out += kDigits[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? kDigits[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? kDigits[v & 63] : '=';
    }
    return out;
}

// An integer with thousands separators: 1234567 -> "1,234,567".
std::string grouped(const std::string& digits) {
    const size_t sign = (!digits.empty() && digits[0] == '-') ? 1 : 0;
    std::string out = digits.substr(0, sign);
    const size_t n = digits.size() - sign;
    for (size_t i = 0; i < n; ++i) {
        if (i > 0 && (n - i) % 3 == 0) out += ',';
        out += digits[sign + i];
    }
    return out;
}

// The value at `pointer`, or null when the report has none (a figure that was not measured).
const nlohmann::json* lookup(const nlohmann::json& report, const std::string& pointer) {
    try {
        const nlohmann::json::json_pointer p(pointer);
        return report.contains(p) ? &report.at(p) : nullptr;
    } catch (const nlohmann::json::exception&) {
        return nullptr;
    }
}

// The text a figure shows: integers grouped, other numbers to `digits` significant digits.
std::string shown(const nlohmann::json& v, int digits) {
    if (v.is_number_integer()) return grouped(v.dump());
    if (v.is_number()) {
        std::ostringstream os;
        os.precision(digits);
        os << v.get<double>();
        return os.str();
    }
    if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
    if (v.is_string()) return v.get<std::string>();
    return v.dump();
}

// A figure as an element: the rounded text, with the pointer and the exact JSON value as attributes.
std::string figure(const char* tag, const nlohmann::json& report, const std::string& pointer, int digits) {
    const nlohmann::json* v = lookup(report, pointer);
    std::string out = std::string("<") + tag + " data-pointer=\"" + escape(pointer) + "\"";
    if (!v || v->is_null()) return out + " class=\"na\">n/a</" + tag + ">";
    return out + " data-value=\"" + escape(v->dump()) + "\">" + escape(shown(*v, digits)) + "</" + tag + ">";
}

std::string dataUri(const Image& image) {
    return "data:" + (image.mimeType.empty() ? std::string("image/png") : image.mimeType) + ";base64," + base64(image.encoded);
}

std::string img(const Image& image, const char* cls, const std::string& alt) {
    std::ostringstream os;
    os << "<figure><img class=\"" << cls << "\" src=\"" << dataUri(image) << "\" alt=\"" << escape(alt) << "\"";
    if (image.width > 0 && image.height > 0) os << " width=\"" << image.width << "\" height=\"" << image.height << "\"";
    os << "><figcaption>" << escape(image.name) << "</figcaption></figure>\n";
    return os.str();
}

std::string anchor(size_t level) { return "level-" + std::to_string(level); }

void writeWarnings(std::ostringstream& os, const HtmlPage& page, const nlohmann::json& report) {
    std::vector<std::string> lines;
    for (const std::string& pointer : page.warningLists) {
        const nlohmann::json* list = lookup(report, pointer);
        if (!list || !list->is_array()) continue;
        for (const nlohmann::json& w : *list) lines.push_back(w.is_string() ? w.get<std::string>() : w.dump());
    }
    if (lines.empty()) {
        os << "<p id=\"warnings\" class=\"ok\">No warnings.</p>\n";
        return;
    }
    os << "<section id=\"warnings\" class=\"warnings\"><h2>Warnings (" << lines.size() << ")</h2><ul>\n";
    for (const std::string& w : lines) os << "<li>" << escape(w) << "</li>\n";
    os << "</ul></section>\n";
}

void writeTable(std::ostringstream& os, const HtmlPage& page, const nlohmann::json& report) {
    const std::vector<HtmlColumn>& cols = page.columns;
    bool groups = false;
    for (const HtmlColumn& c : cols) groups = groups || !c.group.empty();
    os << "<table class=\"figures\"><thead><tr><th" << (groups ? " rowspan=\"2\"" : "") << ">level</th>";
    for (size_t i = 0; i < cols.size();) {
        size_t j = i + 1;
        while (!cols[i].group.empty() && j < cols.size() && cols[j].group == cols[i].group) ++j;
        if (cols[i].group.empty())
            os << "<th" << (groups ? " rowspan=\"2\"" : "") << ">" << escape(cols[i].label) << "</th>";
        else
            os << "<th colspan=\"" << (j - i) << "\">" << escape(cols[i].group) << "</th>";
        i = j;
    }
    os << "</tr>\n";
    if (groups) {
        os << "<tr>";
        for (const HtmlColumn& c : cols)
            if (!c.group.empty()) os << "<th>" << escape(c.label) << "</th>";
        os << "</tr>\n";
    }
    os << "</thead><tbody>\n";
    for (size_t l = 0; l < page.levels.size(); ++l) {
        const HtmlLevel& level = page.levels[l];
        os << "<tr><th><a href=\"#" << anchor(l) << "\">" << escape(level.title) << "</a></th>";
        for (size_t c = 0; c < cols.size(); ++c)
            os << figure("td", report, c < level.pointers.size() ? level.pointers[c] : std::string("/-"), cols[c].digits);
        os << "</tr>\n";
    }
    os << "</tbody></table>\n";
}

void writeLevel(std::ostringstream& os, const HtmlPage& page, const HtmlLevel& level, size_t index) {
    os << "<section class=\"level\" id=\"" << anchor(index) << "\"><h2>" << escape(level.title) << "</h2>\n";
    if (level.views.empty()) {
        os << "<p>No renders.</p>\n";
    } else {
        os << "<p>" << escape(page.viewsCaption) << "</p>\n<div class=\"views\">\n";
        for (const Image& v : level.views) os << img(v, "view", level.title + " " + v.name);
        os << "</div>\n";
    }
    os << "<h3>Texture pages</h3>\n";
    if (level.pages.empty()) {
        os << "<p>None.</p>\n";
    } else {
        os << "<div class=\"pages\">\n";
        for (const Image& p : level.pages) os << img(p, "page", level.title + " " + p.name);
        os << "</div>\n";
    }
    os << "</section>\n";
}

}  // namespace

std::string htmlReport(const HtmlPage& page, const nlohmann::json& report) {
    std::ostringstream os;
    os << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>" << escape(page.title)
       << "</title>\n<style>" << kStyle << "</style></head>\n<body>\n<h1>" << escape(page.title) << "</h1>\n";
    if (!page.facts.empty()) {
        os << "<dl class=\"facts\">\n";
        for (const auto& [label, pointer] : page.facts) os << "<dt>" << escape(label) << "</dt>" << figure("dd", report, pointer, 4) << "\n";
        os << "</dl>\n";
    }
    writeWarnings(os, page, report);
    writeTable(os, page, report);
    for (size_t l = 0; l < page.levels.size(); ++l) writeLevel(os, page, page.levels[l], l);
    os << "</body></html>\n";
    return os.str();
}

void writeHtmlReport(const std::string& path, const HtmlPage& page, const nlohmann::json& report) {
    writeFileAtomic(path, htmlReport(page, report));
}

}  // namespace lodbake

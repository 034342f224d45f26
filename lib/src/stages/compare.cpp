// The compare stage (compare.h): budgets, geometric and image distance of B from A, the tolerances.
#include "lodbake/stages/compare.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "lodbake/core/errors.h"
#include "lodbake/core/pose.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/metrics/review_images.h"
#include "lodbake/texture/codec.h"

namespace lodbake {
namespace {

// --- loading ------------------------------------------------------------------------------

// Bytes on disk: the file, plus for .gltf the external buffers and images it names.
uint64_t fileBytes(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    uint64_t total = fs::file_size(path, ec);
    if (ec) return 0;
    std::string ext = fs::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".gltf") return total;
    std::ifstream in(path);
    nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded()) return total;
    fs::path dir = fs::path(path).parent_path();
    for (const char* key : {"buffers", "images"}) {
        if (!j.contains(key) || !j[key].is_array()) continue;
        for (const auto& e : j[key]) {
            if (!e.contains("uri") || !e["uri"].is_string()) continue;
            std::string uri = e["uri"].get<std::string>();
            if (uri.rfind("data:", 0) == 0) continue;
            std::string decoded;  // percent-decoding
            for (size_t i = 0; i < uri.size(); ++i) {
                if (uri[i] == '%' && i + 2 < uri.size()) {
                    decoded += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
                    i += 2;
                } else {
                    decoded += uri[i];
                }
            }
            uint64_t s = fs::file_size(dir / decoded, ec);
            if (!ec) total += s;
        }
    }
    return total;
}

struct Loaded {
    Asset asset;
    TriMesh mesh;  // the level being compared
    size_t levels = 0;  // levels in LODBAKE_multires (0 if none)
    uint64_t bytes = 0;
    uint64_t drawCalls = 0;
};

Loaded load(const std::string& path, int lod) {
    Loaded l;
    std::optional<Multires> multires;
    // compare decodes the images it renders itself (prepareRenderScene) and only reads the sizes
    // of the others from their headers.
    ReadOptions ro;
    l.asset = readGltf(path, ro, &multires);
    checkImages(l.asset, ImageCheck::Header);
    l.levels = multires ? multires->levels.size() : 0;
    l.bytes = fileBytes(path);
    if (lod > 0 && !multires) {
        // An MSFT_lod chain (pack's output): read level `lod` of each chain in place of LOD0.
        ro.lod = lod;
        l.asset = readGltf(path, ro, nullptr);
        checkImages(l.asset, ImageCheck::Header);
    }
    if (lod == 0 || !multires) {
        l.mesh = std::move(l.asset.mesh);
        l.drawCalls = l.asset.stats.primitives;
    } else {
        if (static_cast<size_t>(lod) > multires->levels.size())
            throw Impossible(path + ": --lod " + std::to_string(lod) + " asked but the file has " +
                             std::to_string(multires->levels.size()) + " levels");
        l.mesh = levelMesh(l.asset.mesh, *multires, static_cast<size_t>(lod));
        l.drawCalls = 0;  // one primitive per used material: taken from the counts
    }
    return l;
}

// --- output -------------------------------------------------------------------------------

nlohmann::json countsJson(const ModelCounts& c, uint64_t bytes) {
    return {{"triangles", c.triangles}, {"vertices", c.vertices},   {"positions", c.positions},
            {"materials", c.materials}, {"drawCalls", c.drawCalls}, {"texels", c.texels},
            {"fileBytes", bytes}};
}

nlohmann::json sideJson(const OneSidedDistance& d, double diag) {
    return {{"max", d.max}, {"mean", d.mean}, {"rms", d.rms}, {"samples", d.samples},
            {"relMax", diag > 0 ? d.max / diag : 0.0}};
}

nlohmann::json imageJson(const ImageMetrics& m) {
    return {{"psnr", m.psnr}, {"worstPsnr", m.worstPsnr}, {"ssim", m.ssim},
            {"worstSsim", m.worstSsim}, {"iou", m.iou}, {"worstIou", m.worstIou},
            {"seamPsnr", m.seamPsnr}, {"seamPixels", m.seamPixels}};
}

std::string fmt(double v, int prec = 6) {
    std::ostringstream os;
    os.precision(prec);
    os << v;
    return os.str();
}

nlohmann::json makeReport(const CompareSettings& s, const CompareResult& r, const Loaded& A, const Loaded& B,
                          const std::vector<std::string>& violations) {
    nlohmann::json j;
    j["tool"] = "compare";
    j["a"] = {{"path", s.a}, {"lod", s.lodA}, {"levels", A.levels}};
    j["b"] = {{"path", s.b}, {"lod", s.lodB}, {"levels", B.levels}};
    j["counts"] = {{"a", countsJson(r.a, A.bytes)}, {"b", countsJson(r.b, B.bytes)}};
    if (s.compare.geometry) {
        const GeometricDistance& d = r.distance;
        j["geometry"] = {{"hausdorff", d.hausdorff}, {"mean", d.mean}, {"rms", d.rms},
                         {"relHausdorff", d.relHausdorff}, {"relMean", d.relMean}, {"relRms", d.relRms},
                         {"diagonal", d.diagonal}, {"aToB", sideJson(d.aToB, d.diagonal)},
                         {"bToA", sideJson(d.bToA, d.diagonal)}};
    }
    if (s.compare.images && s.compare.views > 0) {
        j["images"] = {{"views", s.compare.views}, {"resolution", s.compare.resolution},
                       {"baseColor", imageJson(r.baseColor)}, {"shaded", imageJson(r.shaded)},
                       {"pbr", imageJson(r.pbr)}};
        if (s.verbose > 0) {
            nlohmann::json pv = nlohmann::json::array();
            for (size_t v = 0; v < r.baseColorPerView.size(); ++v)
                pv.push_back({{"baseColor", imageJson(r.baseColorPerView[v])},
                              {"shaded", imageJson(r.shadedPerView[v])},
                              {"pbr", imageJson(r.pbrPerView[v])}});
            j["images"]["perView"] = pv;
        }
    }
    nlohmann::json warn = nlohmann::json::array();
    for (const auto& w : A.asset.warnings) warn.push_back("A: " + w);
    for (const auto& w : B.asset.warnings) warn.push_back("B: " + w);
    for (const auto& w : r.warnings) warn.push_back(w);
    j["warnings"] = warn;
    j["pass"] = violations.empty();
    j["exceeded"] = violations;
    return j;
}

std::string table(const CompareSettings& s, const CompareResult& r, const Loaded& A, const Loaded& B,
                  const std::vector<std::string>& violations) {
    std::ostringstream os;
    auto pad = [](const std::string& v, size_t width) { return v + std::string(v.size() < width ? width - v.size() : 1, ' '); };
    auto row = [&](const std::string& name, const std::string& a, const std::string& b) {
        os << "  " << pad(name, 22) << pad(a, 16) << b << "\n";
    };
    auto row3 = [&](const std::string& name, const std::string& a, const std::string& b, const std::string& c) {
        os << "  " << pad(name, 22) << pad(a, 16) << pad(b, 16) << c << "\n";
    };
    os << "A: " << s.a << (s.lodA ? " (lod " + std::to_string(s.lodA) + ")" : "") << "\n";
    os << "B: " << s.b << (s.lodB ? " (lod " + std::to_string(s.lodB) + ")" : "") << "\n\n";
    row("", "A", "B");
    row("triangles", std::to_string(r.a.triangles), std::to_string(r.b.triangles));
    row("vertices", std::to_string(r.a.vertices), std::to_string(r.b.vertices));
    row("materials", std::to_string(r.a.materials), std::to_string(r.b.materials));
    row("draw calls", std::to_string(r.a.drawCalls), std::to_string(r.b.drawCalls));
    row("texels", std::to_string(r.a.texels), std::to_string(r.b.texels));
    row("file bytes", std::to_string(A.bytes), std::to_string(B.bytes));
    if (s.compare.geometry) {
        const GeometricDistance& d = r.distance;
        os << "\ngeometric distance (A diagonal " << fmt(d.diagonal) << ")\n";
        row("", "absolute", "relative");
        row("hausdorff", fmt(d.hausdorff), fmt(d.relHausdorff));
        row("mean", fmt(d.mean), fmt(d.relMean));
        row("rms", fmt(d.rms), fmt(d.relRms));
        row("A->B max", fmt(d.aToB.max), fmt(d.diagonal > 0 ? d.aToB.max / d.diagonal : 0));
        row("B->A max", fmt(d.bToA.max), fmt(d.diagonal > 0 ? d.bToA.max / d.diagonal : 0));
    }
    if (s.compare.images && s.compare.views > 0) {
        os << "\nimages (" << s.compare.views << " views, " << s.compare.resolution << "x" << s.compare.resolution << ")\n";
        row3("", "base colour", "shaded", "pbr");
        row3("psnr dB", fmt(r.baseColor.psnr, 5), fmt(r.shaded.psnr, 5), fmt(r.pbr.psnr, 5));
        row3("worst view psnr dB", fmt(r.baseColor.worstPsnr, 5), fmt(r.shaded.worstPsnr, 5), fmt(r.pbr.worstPsnr, 5));
        row3("seam band psnr dB", fmt(r.baseColor.seamPsnr, 5), fmt(r.shaded.seamPsnr, 5), fmt(r.pbr.seamPsnr, 5));
        row3("ssim", fmt(r.baseColor.ssim, 5), fmt(r.shaded.ssim, 5), fmt(r.pbr.ssim, 5));
        row3("silhouette iou", fmt(r.baseColor.iou, 5), fmt(r.shaded.iou, 5), fmt(r.pbr.iou, 5));
        auto psnrSsim = [](const ImageMetrics& m) { return fmt(m.psnr, 4) + "/" + fmt(m.ssim, 3); };
        if (s.verbose > 0)
            for (size_t v = 0; v < r.baseColorPerView.size(); ++v)
                row3("view " + std::to_string(v) + " psnr/ssim", psnrSsim(r.baseColorPerView[v]),
                     psnrSsim(r.shadedPerView[v]), psnrSsim(r.pbrPerView[v]));
    }
    os << "\n" << (violations.empty() ? "result: pass" : "result: FAIL") << "\n";
    for (const std::string& v : violations) os << "  exceeded: " << v << "\n";
    return os.str();
}

// --- tolerances ---------------------------------------------------------------------------

std::vector<std::string> checkTolerances(const CompareTolerances& t, const CompareResult& r, const CompareOptions& o) {
    std::vector<std::string> v;
    auto above = [&](const char* name, const std::optional<double>& lim, double value) {
        if (lim && !(value <= *lim)) v.push_back(std::string(name) + " " + fmt(value) + " > " + fmt(*lim));
    };
    auto below = [&](const char* name, const std::optional<double>& lim, double value) {
        if (lim && !(value >= *lim)) v.push_back(std::string(name) + " " + fmt(value) + " < " + fmt(*lim));
    };
    if (o.geometry) {
        above("relative hausdorff", t.maxHausdorff, r.distance.relHausdorff);
        above("relative rms", t.maxRms, r.distance.relRms);
    }
    if (o.images && o.views > 0) {
        below("base colour psnr", t.minPsnr, r.baseColor.psnr);
        below("shaded psnr", t.minShadedPsnr, r.shaded.psnr);
        below("pbr psnr", t.minPbrPsnr, r.pbr.psnr);
        below("silhouette iou", t.minIou, std::min(r.baseColor.iou, r.shaded.iou));
        below("ssim", t.minSsim, std::min(r.baseColor.ssim, r.shaded.ssim));
    }
    return v;
}

// The time of s.pose in seconds. \throw Impossible when A has no such animation.
double poseTime(const CompareSettings& s, const Loaded& A) {
    const ComparePose& p = s.pose;
    const std::vector<Animation>& anims = A.asset.rig.animations;
    if (size_t(p.animation) >= anims.size())
        throw Impossible(s.a + ": --animation " + std::to_string(p.animation) + " asked but the file has " + std::to_string(anims.size()) +
                         " animations");
    const TimeRange r = animationTimes(anims[size_t(p.animation)]);
    switch (p.at) {
        case ComparePose::At::Start: return r.start;
        case ComparePose::At::Middle: return 0.5 * (r.start + r.end);
        case ComparePose::At::End: return r.end;
        default: return p.seconds;
    }
}

// What --html shows: B's figures in one row (A's counts as facts), B's pictures.
HtmlPage htmlPage(const CompareSettings& s, const CompareStageResult& out) {
    HtmlPage page;
    page.title = "compare: " + std::filesystem::path(s.b).filename().string() + (s.lodB ? " LOD " + std::to_string(s.lodB) : "") +
                 " against " + std::filesystem::path(s.a).filename().string();
    page.facts = {{"A", "/a/path"},           {"A level", "/a/lod"},         {"B", "/b/path"},
                  {"B level", "/b/lod"},       {"A triangles", "/counts/a/triangles"}, {"A texels", "/counts/a/texels"},
                  {"A bytes", "/counts/a/fileBytes"}, {"views", "/images/views"}, {"pass", "/pass"}};
    page.warningLists = {"/exceeded", "/warnings"};
    page.viewsCaption = "Each view: A | B | |A - B| x 4, lit (pbr) renders.";
    HtmlLevel b;
    b.title = s.lodB ? "B LOD " + std::to_string(s.lodB) : "B";
    const std::pair<HtmlColumn, std::string> counts[] = {
        {{"", "triangles"}, "/counts/b/triangles"},     {{"", "draw calls"}, "/counts/b/drawCalls"},
        {{"", "texels"}, "/counts/b/texels"},           {{"", "bytes"}, "/counts/b/fileBytes"},
        {{"distance / diagonal", "Hausdorff"}, "/geometry/relHausdorff"}, {{"distance / diagonal", "RMS"}, "/geometry/relRms"}};
    for (const auto& [column, pointer] : counts) {
        page.columns.push_back(column);
        b.pointers.push_back(pointer);
    }
    for (const auto& [column, pointer] : compareImageFigures("")) {
        page.columns.push_back(column);
        b.pointers.push_back(pointer);
    }
    b.views = out.views;
    b.pages = out.pages;
    page.levels.push_back(std::move(b));
    return page;
}

}  // namespace

std::vector<std::pair<HtmlColumn, std::string>> compareImageFigures(const std::string& base) {
    std::vector<std::pair<HtmlColumn, std::string>> out;
    const std::pair<const char*, const char*> modes[] = {{"colour", "baseColor"}, {"shape", "shaded"}, {"lit", "pbr"}};
    for (const auto& [label, key] : modes) out.push_back({{"PSNR dB", label}, base + "/images/" + key + "/psnr"});
    for (const auto& [label, key] : modes) out.push_back({{"SSIM", label}, base + "/images/" + key + "/ssim"});
    out.push_back({{"IoU", "lit"}, base + "/images/pbr/iou"});
    return out;
}

CompareStageResult runCompare(const CompareSettings& s) {
    Loaded A = load(s.a, s.lodA);
    Loaded B = load(s.b, s.lodB);
    double time = 0;
    if (s.pose.animation >= 0) {
        time = poseTime(s, A);
        if (size_t(s.pose.animation) >= B.asset.rig.animations.size())
            B.asset.warnings.push_back("no animation " + std::to_string(s.pose.animation) + ": compared in its rest pose");
        A.mesh = poseMesh(A.asset.rig, A.asset.morph, A.mesh, s.pose.animation, time);
        B.mesh = poseMesh(B.asset.rig, B.asset.morph, B.mesh, s.pose.animation, time);
    }
    CompareOptions opt = s.compare;
    opt.threads = s.threads;
    const bool pictures = s.pictures || !s.html.empty();
    opt.keepRenders = !s.sheet.empty() || pictures;
    CompareResult r = compareAssets(A.asset, A.mesh, B.asset, B.mesh, opt);
    if (A.drawCalls) r.a.drawCalls = A.drawCalls;
    if (B.drawCalls) r.b.drawCalls = B.drawCalls;

    CompareStageResult out;
    out.exceeded = checkTolerances(s.tolerances, r, opt);
    out.report = makeReport(s, r, A, B, out.exceeded);
    if (s.pose.animation >= 0) out.report["pose"] = {{"animation", s.pose.animation}, {"time", time}};
    if (!s.sheet.empty()) writeContactSheet(s.sheet, r);
    if (pictures) {
        out.views = viewStrips(r);
        out.pages = pageThumbnails(B.asset, B.mesh);
    }
    r.rendersA.clear();
    r.rendersB.clear();
    if (!s.report.empty()) writeReport(s.report, out.report);
    if (!s.html.empty()) writeHtmlReport(s.html, htmlPage(s, out), out.report);
    out.statistics = s.json ? out.report.dump(2) + "\n" : table(s, r, A, B, out.exceeded);
    return out;
}

}  // namespace lodbake

// compare A B [options]: how far B (usually a LOD) is from A (usually the original) —
// budgets, geometric distance and image distance (DESIGN.md "How we judge output").
// Parses the flags into CompareSettings, validates them before loading and runs the stage
// (lodbake/stages/compare.h); exit code 1 when a tolerance is exceeded.
#include <filesystem>

#include "common/cli.h"
#include "lodbake/core/math.h"
#include "lodbake/stages/compare.h"

namespace lodbake {
namespace {

const char* kSynopsis =
    "A.glb B.glb [options]\n"
    "\n"
    "Compares B with A: triangles, vertices, materials, draw calls, texels, file bytes;\n"
    "two-sided Hausdorff / mean / RMS surface distance (area-weighted samples, AABB tree),\n"
    "absolute and relative to A's bounding-box diagonal; renders of both from the same views\n"
    "(Fibonacci sphere, 30 deg like a viewer's camera, framing A's bounding sphere) in unlit\n"
    "base colour, in Lambert-shaded grey and lit with every PBR material channel\n"
    "(docs/compare.md),\n"
    "with PSNR (over pixels covered by either silhouette, capped at\n"
    "100 dB for identical images), SSIM (luminance, 8x8 windows) and silhouette IoU.\n"
    "Results are identical for any --threads.";

const char* kExitCodes =
    "Exit codes of compare (code 1 also means a tolerance was exceeded, for CI):\n"
    "  0 every given tolerance holds, 1 a tolerance is exceeded or a usage error,\n"
    "  2 unreadable or invalid input, 3 --lod level or --animation not present, 4 internal failure.\n";

int run(const CompareSettings& s) {
    CompareStageResult r = runCompare(s);
    std::cout << r.statistics;
    for (const std::string& v : r.exceeded) std::cerr << "compare: tolerance exceeded: " << v << "\n";
    return r.exceeded.empty() ? cli::kOk : cli::kUsage;
}

}  // namespace
}  // namespace lodbake

int main(int argc, char** argv) {
    using namespace lodbake;
    return cli::runTool("compare", [&]() -> int {
        CompareSettings s;
        cli::ArgParser p("compare", kSynopsis);
        p.exitCodes(kExitCodes);
        std::vector<std::string> files;
        p.positionals("A B", [&](const std::string& v) { files.push_back(v); });
        auto nonNegative = [](const std::string& flag, const std::string& v) {
            double d = cli::parseDouble(flag, v);
            if (d < 0) throw UsageError(flag + " must be >= 0");
            return d;
        };
        p.option("--lod", "K", "compare level K of B (LODBAKE_multires level, or MSFT_lod level; 0 = the original / LOD0)", [&](const std::string& v) {
            s.lodB = cli::parseInt("--lod", v);
            if (s.lodB < 0) throw UsageError("--lod must be >= 0");
        });
        p.option("--lod-a", "K", "compare level K of A (LODBAKE_multires or MSFT_lod; default 0)", [&](const std::string& v) {
            s.lodA = cli::parseInt("--lod-a", v);
            if (s.lodA < 0) throw UsageError("--lod-a must be >= 0");
        });
        p.option("--animation", "N", "pose A and B with their animation N (0 = the first) before comparing", [&](const std::string& v) {
            s.pose.animation = cli::parseInt("--animation", v);
            if (s.pose.animation < 0) throw UsageError("--animation must be >= 0");
        });
        p.option("--time", "T", "with --animation: the time posed, seconds, or start, middle or end of A's animation (default start)",
                 [&](const std::string& v) {
                     using At = ComparePose::At;
                     if (v == "start") s.pose.at = At::Start;
                     else if (v == "middle") s.pose.at = At::Middle;
                     else if (v == "end") s.pose.at = At::End;
                     else { s.pose.at = At::Seconds; s.pose.seconds = cli::parseDouble("--time", v); }
                 });
        p.option("--views", "N", "render views (default " + std::to_string(s.compare.views) + "; 0 = no image comparison)", [&](const std::string& v) {
            s.compare.views = cli::parseInt("--views", v);
            if (s.compare.views < 0 || s.compare.views > 4096) throw UsageError("--views must be in [0, 4096]");
        });
        p.option("--resolution", "R", "render size in pixels (default " + std::to_string(s.compare.resolution) + ")", [&](const std::string& v) {
            s.compare.resolution = cli::parseInt("--resolution", v);
            if (s.compare.resolution < 8 || s.compare.resolution > 8192)
                throw UsageError("--resolution must be in [8, 8192]");
        });
        p.option("--fov", "DEG",
                 "vertical field of view of the renders (default " + cli::number(s.compare.fovY * 180 / kPi) +
                     "); the cameras sit at radius / sin(fov/2) from the centre, so a small angle approximates an "
                     "orthographic view",
                 [&](const std::string& v) {
                     double deg = cli::parseDouble("--fov", v);
                     if (!(deg >= 0.5 && deg <= 120)) throw UsageError("--fov must be in [0.5, 120]");
                     s.compare.fovY = deg * kPi / 180;
                 });
        p.option("--samples", "N", "area samples per side (default " + std::to_string(s.compare.distance.samplesPerSide) +
                     "; 0 = vertices only)", [&](const std::string& v) {
            int n = cli::parseInt("--samples", v);
            if (n < 0) throw UsageError("--samples must be >= 0");
            s.compare.distance.samplesPerSide = static_cast<size_t>(n);
        });
        p.flag("--no-geometry", "skip the geometric distance", [&] { s.compare.geometry = false; });
        p.option("--max-hausdorff", "X", "tolerance: Hausdorff distance / A's diagonal <= X",
                 [&](const std::string& v) { s.tolerances.maxHausdorff = nonNegative("--max-hausdorff", v); });
        p.option("--max-rms", "X", "tolerance: RMS distance / A's diagonal <= X",
                 [&](const std::string& v) { s.tolerances.maxRms = nonNegative("--max-rms", v); });
        p.option("--min-psnr", "DB", "tolerance: base-colour PSNR >= DB",
                 [&](const std::string& v) { s.tolerances.minPsnr = cli::parseDouble("--min-psnr", v); });
        p.option("--min-shaded-psnr", "DB", "tolerance: shaded PSNR >= DB",
                 [&](const std::string& v) { s.tolerances.minShadedPsnr = cli::parseDouble("--min-shaded-psnr", v); });
        p.option("--min-pbr-psnr", "DB", "tolerance: PBR-lit PSNR >= DB",
                 [&](const std::string& v) { s.tolerances.minPbrPsnr = cli::parseDouble("--min-pbr-psnr", v); });
        p.option("--min-iou", "X", "tolerance: silhouette IoU >= X (base colour and shaded)",
                 [&](const std::string& v) { s.tolerances.minIou = cli::parseDouble("--min-iou", v); });
        p.option("--min-ssim", "X", "tolerance: SSIM >= X (base colour and shaded)",
                 [&](const std::string& v) { s.tolerances.minSsim = cli::parseDouble("--min-ssim", v); });
        p.option("--sheet", "FILE.png", "write a contact sheet (rows: views; A, B, |A-B|x4 per mode)",
                 [&](const std::string& v) { s.sheet = v; });
        p.option("--html", "FILE.html",
                 "write a self-contained HTML report: the figures of the JSON report, per view A | B | |A-B|x4 "
                 "(lit renders, up to 4 views), B's texture pages",
                 [&](const std::string& v) { s.html = v; });
        p.flag("--json", "print the JSON report on stdout instead of the table", [&] { s.json = true; });
        p.option("--report", "FILE.json", "write the JSON report to FILE.json", [&](const std::string& v) { s.report = v; });
        p.flag("-v", "more figures (per-view image metrics)", [&] { s.verbose = 1; });
        p.option("--threads", "N", "worker threads (0 = all cores); output is identical for any N", [&](const std::string& v) {
            s.threads = cli::parseInt("--threads", v);
            if (s.threads < 0) throw UsageError("--threads must be >= 0");
        });
        if (!p.parse(argc, argv)) return cli::kOk;
        if (files.size() != 2) throw UsageError("expected two files, A and B (got " + std::to_string(files.size()) + ")");
        s.a = files[0];
        s.b = files[1];
        namespace fs = std::filesystem;
        std::error_code ec;
        for (const std::string& f : files)
            if (!fs::is_regular_file(f, ec)) throw IOError(f + ": no such file");
        for (const std::string& out : {s.report, s.sheet, s.html}) {
            if (out.empty()) continue;
            fs::path parent = fs::path(out).parent_path();
            if (!parent.empty() && !fs::is_directory(parent, ec))
                throw IOError(out + ": folder '" + parent.string() + "' does not exist");
            if (fs::is_directory(out, ec)) throw IOError(out + ": is a folder");
            for (const std::string& in : files)
                if (fs::weakly_canonical(in, ec) == fs::weakly_canonical(out, ec))
                    throw UsageError("'" + out + "' would overwrite the input " + in);
        }
        if (!s.sheet.empty() && s.compare.views == 0) throw UsageError("--sheet needs --views > 0");
        return run(s);
    });
}

// The pack stage (pack.h): load, packLodChain(), write the chain (pack_write.h), report.
#include "lodbake/stages/pack.h"

#include "lodbake/core/errors.h"
#include "lodbake/core/timing.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/texture/codec.h"

namespace lodbake {
namespace {

nlohmann::json makeReport(const PackSettings& s, const Asset& asset, const Multires& multires, const PackResult& res,
                          const PackProfile& time, const PackWriteStats& ws, double loadSeconds, double writeSeconds) {
    const PackOptions& o = s.pack;
    const LodChainWriteOptions& c = s.write.chain;
    nlohmann::json levels = nlohmann::json::array();
    for (size_t k = 0; k < res.reports.size(); ++k) {
        const PackLevelReport& r = res.reports[k];
        const PackLevelProfile& t = time.levels[k];
        auto cache = [](const VertexCacheStats& v) { return nlohmann::json{{"acmr", v.acmr}, {"atvr", v.atvr}}; };
        auto steps = [](const PackLevelProfile::Steps& st) {
            return nlohmann::json{{"uvs", st.uvs}, {"page", st.page}, {"mesh", st.mesh}, {"bake", st.bake}, {"material", st.material}};
        };
        levels.push_back({{"lod", k},
                          {"source", r.source},
                          {"triangles", r.triangles},
                          {"vertices", r.vertices},
                          {"drawCalls", r.drawCalls},
                          {"materials", r.materials},
                          {"texels", uint64_t(r.width) * uint64_t(r.height)},
                          {"width", r.width},
                          {"height", r.height},
                          {"bytes", ws.levelBytes[k]},
                          {"geometryBytes", ws.levelGeometryBytes[k]},
                          {"imageBytes", ws.levelImageBytes[k]},
                          {"vertexCache", {{"cacheSize", 16}, {"before", cache(ws.cacheBefore[k])}, {"after", cache(ws.cacheAfter[k])}}},
                          {"charts", r.charts},
                          {"absorbedIslands", r.absorbedIslands},
                          {"gutter", r.gutter},
                          {"mips", r.mips},
                          {"utilisation", r.utilisation},
                          {"boxUtilisation", r.boxUtilisation},
                          {"rasterUtilisation", r.rasterUtilisation},
                          {"footprintUtilisation", r.footprintUtilisation},
                          {"texelsPerUnit", r.texelsPerUnit},
                          {"texelLimit", r.texelLimit},
                          {"deviation", {{"hausdorff", r.hausdorff}, {"relHausdorff", r.relHausdorff}, {"rms", r.rms},
                                         {"relRms", r.relRms}, {"simplifyMax", r.maxDeviation}}},
                          {"screenCoverage", r.coverage},
                          {"maxScreenCoverage", r.maxCoverage},
                          {"switchDistance", r.switchDistance},
                          {"bakeSeconds", t.bakeSeconds},
                          {"seconds", steps(t.wall)},
                          {"cpuSeconds", steps(t.cpu)},
                          {"channels", r.channels},
                          {"textureRank", r.rank},
                          {"pageSideNeeded", r.sideNeeded},
                          {"hierarchyTextureSize", r.textureSize}});
        if (k == 0)
            levels.back()["sourceTexels"] = r.sourceTexelsNote.empty()
                                                ? nlohmann::json{{"used", r.sourceTexels}}
                                                : nlohmann::json{{"used", r.sourceTexels}, {"why", r.sourceTexelsNote}};
        if (!r.tiling.note.empty())
            levels.back()["tiling"] = {{"tiled", r.tiling.tiled}, {"why", r.tiling.note}, {"span", r.tiling.span},
                                       {"rechosenTriangles", r.tiling.rechosen}, {"stretchedTriangles", r.tiling.stretched},
                                       {"stretchedArea", r.tiling.stretchedArea}};
        if (!r.rankChoice.candidates.empty()) {
            const PackLevelReport::RankChoice& rc = r.rankChoice;
            nlohmann::json candidates = nlohmann::json::array();
            for (const PackLevelReport::RankChoice::Candidate& c : rc.candidates)
                candidates.push_back({{"rank", c.rank}, {"score", c.score}, {"baseColorRms", c.baseColor}, {"normalRms", c.normal},
                                      {"width", c.width}, {"height", c.height}, {"charts", c.charts}});
            levels.back()["rankChoice"] = {{"candidates", candidates}, {"chosen", r.rank}, {"byEnergy", rc.byEnergy},
                                           {"reason", rc.reason}, {"seconds", t.rankChoiceSeconds},
                                           {"cpuSeconds", t.rankChoiceCpuSeconds}};
        }
        if (!r.splitBy.empty()) levels.back()["splitBy"] = r.splitBy;
        if (!r.variants.empty()) {
            nlohmann::json variants = nlohmann::json::array();
            for (const PackLevelReport::Variant& v : r.variants)
                variants.push_back({{"name", v.name}, {"material", v.material}, {"channels", v.channels}});
            levels.back()["variants"] = variants;
        }
        if (r.placement.tried) {
            const PackLevelReport::Placement& pl = r.placement;
            levels.back()["placement"] = {{"applied", pl.applied},
                                          {"before", {{"hausdorff", pl.hausdorff}, {"relHausdorff", pl.relHausdorff},
                                                      {"rms", pl.rms}, {"relRms", pl.relRms}}},
                                          {"movedVertices", pl.moved}, {"fixedVertices", pl.fixed},
                                          {"shortenedSteps", pl.shortened}, {"rounds", pl.rounds},
                                          {"seconds", t.placementSeconds}, {"placeSeconds", t.placeSeconds}};
            if (!pl.skipped.empty()) levels.back()["placement"]["skipped"] = pl.skipped;
        }
    }
    nlohmann::json rep;
    rep["tool"] = "pack";
    rep["input"] = {{"path", s.common.input}, {"triangles", asset.mesh.triangleCount()}, {"levels", multires.levels.size()},
                    {"charts", multires.charts.chartCount}};
    rep["output"] = {{"path", s.common.output}, {"files", ws.files}, {"bytes", ws.totalBytes}};
    rep["options"] = {{"pixelError", o.pixelError}, {"viewportHeight", o.viewportHeight}, {"fov", o.fovY},
                      {"cutoffPixels", o.cutoffPixels}, {"maxSize", o.maxSize}, {"pot", o.powerOfTwo},
                      {"maxMips", o.maxMips},
                      {"imageFormat", s.imageFormatName.empty() ? imageFormatName(o.imageFormat) : s.imageFormatName},
                      {"jpegQuality", o.jpegQuality}, {"split", s.write.split}, {"textureHierarchy", o.useTextureHierarchy},
                      {"lod0Density", o.lod0Density}, {"draco", c.draco},
                      {"optimize", c.optimize}, {"meshopt", c.meshopt}, {"quantize", c.quantize}, {"normalMaps", normalMapsName(o.normalMaps)},
                      {"baseColorOnly", o.baseColorOnly}, {"projectLevels", o.projectLevels},
                      {"vertexPlacement", o.vertexPlacement},
                      {"qp", c.quantPosition}, {"qt", c.quantTexcoord}, {"qn", c.quantNormal}, {"lod0", lod0Name(o.lod0)},
                      {"maxDraws", o.maxDraws}};
    nlohmann::json lod0 = {{"mode", lod0Name(o.lod0)}};
    if (res.original) {
        const SourceScene& src = *res.original;
        lod0.update({{"path", src.path}, {"drawCalls", src.drawCalls}, {"materials", src.materials}, {"meshes", src.meshes},
                     {"nodes", src.nodes}, {"textures", src.textures}, {"images", src.images}, {"skins", src.skins},
                     {"animations", src.animations}, {"triangles", src.triangles}, {"decoded", src.decoded}});
    }
    rep["lod0"] = lod0;
    rep["utilisationDefinition"] = "chart texels / page texels; chart texels = the charts' triangle coverage (UV area); "
                                   "boxUtilisation uses the charts' rotated bounding rectangles (above 1 when charts nest), "
                                   "rasterUtilisation the texels their triangles touch, footprintUtilisation adds each "
                                   "chart's gutter ring (which may reach past the page border)";
    rep["radius"] = res.radius;
    rep["diagonal"] = res.diagonal;
    rep["screenCoverage"] = res.screenCoverage;
    rep["levels"] = levels;
    std::vector<std::string> warnings = asset.warnings;
    warnings.insert(warnings.end(), res.warnings.begin(), res.warnings.end());
    warnings.insert(warnings.end(), ws.warnings.begin(), ws.warnings.end());
    rep["warnings"] = warnings;
    rep["time"] = {{"load", loadSeconds}, {"pack", time.seconds}, {"measure", time.measureSeconds}, {"measureCpu", time.measureCpuSeconds}, {"write", writeSeconds}};
    return rep;
}

std::string statistics(const PackSettings& s, const PackResult& res, const PackProfile& time, const PackWriteStats& ws,
                       double writeSeconds) {
    std::string out;
    appendf(out, "lod  triangles  page        util   box    gutter  hausdorff(rel)  coverage\n");
    for (size_t k = 0; k < res.reports.size(); ++k) {
        const PackLevelReport& r = res.reports[k];
        appendf(out, "%3zu  %9zu  %4dx%-5d  %5.1f%% %5.1f%% %6d  %.3g (%.2e)  %.4g\n", k, r.triangles, r.width, r.height,
                100 * r.utilisation, 100 * r.boxUtilisation, r.gutter, r.hausdorff, r.relHausdorff, r.coverage);
    }
    appendf(out, "output: %s (%llu bytes), time: pack %.2fs, write %.2fs\n", s.common.output.c_str(),
            static_cast<unsigned long long>(ws.totalBytes), time.seconds, writeSeconds);
    return out;
}

}  // namespace

const char* imageFormatName(ImageFormat format) { return format == ImageFormat::Png ? "png" : "jpeg"; }

const char* lod0Name(Lod0 mode) { return mode == Lod0::Original ? "original" : "baked"; }

const char* normalMapsName(NormalMaps mode) {
    return mode == NormalMaps::Auto ? "auto" : mode == NormalMaps::Always ? "always" : "never";
}

StageResult runPack(const PackSettings& s) {
    std::optional<Multires> multires;
    double loadSeconds = 0;
    Asset asset = loadStageInput(s.common, loadSeconds, &multires, checkImages);
    if (!multires) throw Impossible(s.common.input + ": no LODBAKE_multires extension; run simplify and parameterize first");

    PackOptions opt = s.pack;
    opt.threads = s.common.threads;
    opt.progress = s.common.progress;
    PackProfile time;
    opt.profile = &time;
    PackResult res = packLodChain(asset, *multires, opt);

    Clock::time_point t1 = Clock::now();
    PackWriteOptions write = s.write;
    write.chain.threads = s.common.threads;
    PackWriteStats ws = writePackResult(s.common.output, res, write);
    double writeSeconds = secondsSince(t1);

    StageResult out;
    out.report = makeReport(s, asset, *multires, res, time, ws, loadSeconds, writeSeconds);
    if (!s.common.report.empty()) writeReport(s.common.report, out.report);
    if (s.common.verbose) out.statistics = statistics(s, res, time, ws, writeSeconds);
    return out;
}

}  // namespace lodbake

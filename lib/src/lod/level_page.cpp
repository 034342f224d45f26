// A level's page (level_page.h): layouts, level UVs, own charts and the page search.
#include "lod/level_page.h"

#include <algorithm>
#include <cmath>

#include "lodbake/bake/bake.h"
#include "lodbake/chart/level_charts.h"
#include "lodbake/core/closest_point.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/core/math.h"
#include "lodbake/core/parallel.h"
#include "lod/level_islands.h"
#include "lod/level_plan.h"

namespace lodbake::lod_detail {
namespace {

void addIslands(const ChartLayout& ch, LayoutData& d) {
    for (uint32_t i = 0; i < ch.islands.size(); ++i) {
        const LayoutIsland& isl = ch.islands[i];
        d.island.emplace(islandKey(isl.vertices), i);
        d.chartUvArea.push_back(triangleArea(isl.uv[0], isl.uv[1], isl.uv[2]));
    }
}

// The layout chart (or island) whose original faces chart c of a level's UVs covers; >= the
// layout's chartCount + islands for a level's own chart grown from islands (no original faces).
uint32_t layoutChartOf(const LevelUVs& luv, uint32_t c) { return luv.ownChartArea.empty() ? c : luv.ownChartSource[c]; }

// The UV area chart c of a level's UVs takes: its footprint's, at least.
double levelChartArea(const LayoutData& L, const LevelUVs& luv, uint32_t c) {
    const uint32_t source = layoutChartOf(luv, c);
    const double layout = source < L.ch->chartCount || luv.ownChartArea.empty() ? L.chartUvArea[source] : 0;
    return luv.ownChartArea.empty() ? layout : std::max(layout, luv.ownChartArea[c]);
}

}  // namespace

const std::vector<std::vector<uint32_t>>& islandFacesOf(const TriMesh& mesh, LayoutData& d) {
    if (!d.islandFacesFound) {
        std::vector<BakeIsland> bake = layoutBakeIslands(mesh, *d.ch);
        d.islandFaces.reserve(bake.size());
        for (BakeIsland& b : bake) d.islandFaces.push_back(std::move(b.faces));
        d.islandFacesFound = true;
    }
    return d.islandFaces;
}

LayoutData layoutData(const Asset& asset, const ChartLayout& ch, uint32_t rank) {
    const TriMesh& mesh = asset.mesh;
    if (ch.faceChart.size() != mesh.triangleCount() || ch.cornerUV.size() != mesh.triangleCount())
        throw InvalidInput(asset.sourcePath + ": chart layout does not match the original mesh");
    for (uint32_t c : ch.faceChart)
        if (c >= ch.chartCount) throw InvalidInput(asset.sourcePath + ": chart id out of range");
    LayoutData d;
    d.ch = &ch;
    d.rank = rank;
    d.chartFaces.resize(ch.chartCount);
    d.chartUvArea.assign(ch.chartCount, 0);
    double uvTotal = 0, areaTotal = 0;
    for (size_t f = 0; f < mesh.triangleCount(); ++f) {
        uint32_t c = ch.faceChart[f];
        d.chartFaces[c].push_back(uint32_t(f));
        double a = triangleArea(ch.cornerUV[f][0], ch.cornerUV[f][1], ch.cornerUV[f][2]);
        d.chartUvArea[c] += a;
        uvTotal += a;
        const Tri& t = mesh.triangles[f];
        areaTotal += triangleArea(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    }
    if (!(uvTotal > 0) || !(areaTotal > 0)) throw Impossible(asset.sourcePath + ": the chart layout has no area");
    d.uvPerUnit = std::sqrt(uvTotal / areaTotal);
    d.lookup = std::make_unique<ChartVertexUV>(mesh, ch);
    addIslands(ch, d);
    return d;
}

std::vector<LayoutData> layoutsOf(const Asset& asset, const Multires& mr, bool hierarchy) {
    std::vector<LayoutData> layouts;
    layouts.push_back(layoutData(asset, mr.charts, 0));
    if (hierarchy)
        for (size_t j = 0; j < mr.textures.ranks.size(); ++j) layouts.push_back(layoutData(asset, mr.textures.ranks[j], uint32_t(j + 1)));
    return layouts;
}

// Every layout (T0 and the hierarchy's ranks): the chart levelTriangleCharts picks (the face's, or
// one holding all three corners), a corner outside it the UV of the closest point of the chart's
// surface: the level UVs parameterize writes and guards against folds for that layout. A level
// triangle with an island's vertex triple takes the island (parameterize's fallback for a level
// triangle that would fold in its chart).
LevelUVs levelUVs(const TriMesh& mesh, const LayoutData& L, const LevelView& lv, const Level* level, int threads) {
    const ChartLayout& ch = *L.ch;
    LevelUVs out;
    const size_t n = lv.triangles.size();
    out.chart.resize(n);
    out.uv.resize(n);
    if (!level) {  // the original triangles
        for (size_t t = 0; t < n; ++t) {
            out.chart[t] = ch.faceChart[lv.faces[t]];
            out.uv[t] = ch.cornerUV[lv.faces[t]];
        }
        return out;
    }
    out.chart = levelTriangleCharts(mesh, ch.faceChart, ch.chartCount, *level);
    // (1) Islands and the corners their chart holds; the others, (chart << 32 | vertex), listed
    // per chunk of triangles and marked in `outsideCorners` (bit j of triangle t).
    constexpr size_t kChunk = 16384;
    std::vector<std::vector<uint64_t>> outside(chunkCount(n, kChunk));
    std::vector<uint8_t> outsideCorners(n, 0);
    parallelChunks(n, kChunk, threads, [&](size_t begin, size_t end, size_t) {
        std::vector<uint64_t>& list = outside[begin / kChunk];
        for (size_t t = begin; t < end; ++t) {
            if (!L.island.empty()) {
                auto isl = L.island.find(islandKey(lv.triangles[t]));
                if (isl != L.island.end()) {
                    const LayoutIsland& island = ch.islands[isl->second];
                    out.chart[t] = ch.chartCount + isl->second;
                    for (size_t j = 0; j < 3; ++j) out.uv[t][j] = island.uvOf(lv.triangles[t][j]);
                    continue;
                }
            }
            const uint32_t c = out.chart[t];
            for (size_t j = 0; j < 3; ++j) {
                const uint32_t v = lv.triangles[t][j];
                if (L.lookup->has(v, c)) {
                    out.uv[t][j] = (*L.lookup)(v, c);
                } else {
                    outsideCorners[t] |= uint8_t(1u << j);
                    list.push_back(uint64_t(c) << 32 | v);
                }
            }
        }
    });
    // (2) Each outside corner's UV: the closest point of its chart's surface, once per pair.
    std::vector<uint64_t> pairs;
    for (std::vector<uint64_t>& list : outside) pairs.insert(pairs.end(), list.begin(), list.end()), std::vector<uint64_t>().swap(list);
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    // The search's grid over the original is built for the first pair and freed with it: held
    // for the whole chain it would sit under every later peak.
    FaceSetSearch search(mesh, threads);
    std::vector<Vec2> projected(pairs.size());
    parallelFor(pairs.size(), threads, [&](size_t i) {
        const uint32_t c = uint32_t(pairs[i] >> 32), v = uint32_t(pairs[i]);
        projected[i] = search.closestUV(ch.cornerUV, L.chartFaces[c], mesh.positions[v]);
    });
    // (3) The marked corners take them.
    if (!pairs.empty())
        parallelChunks(n, kChunk, threads, [&](size_t begin, size_t end, size_t) {
            for (size_t t = begin; t < end; ++t)
                for (size_t j = 0; j < 3; ++j)
                    if (outsideCorners[t] >> j & 1u) {
                        const uint64_t key = uint64_t(out.chart[t]) << 32 | lv.triangles[t][j];
                        out.uv[t][j] = projected[size_t(std::lower_bound(pairs.begin(), pairs.end(), key) - pairs.begin())];
                    }
        });
    return out;
}

LevelUVs ownCharts(const TriMesh& mesh, const LayoutData& L, const LevelView& lv, LevelUVs luv) {
    LevelChartSet set = absorbIslands(lv.positionsOr(mesh), lv.triangles, luv.chart, luv.uv, L.ch->chartCount, L.uvPerUnit);
    LevelUVs out;
    out.chart = std::move(set.chart);
    out.uv = std::move(set.uv);
    out.ownChartArea = std::move(set.uvArea);
    out.ownChartSource = std::move(set.source);
    out.absorbedIslands = set.absorbed + set.grouped;
    return out;
}

namespace {

// The level's charts as packAtlas takes them; la.chartSlot and la.charts say where each went.
std::vector<AtlasChart> levelAtlasCharts(const LayoutData& L, const LevelUVs& luv, bool original, LevelAtlas& la) {
    const ChartLayout& ch = *L.ch;
    const bool own = !luv.ownChartArea.empty();
    la.chartSlot.assign(own ? luv.ownChartArea.size() : L.chartUvArea.size(), -1);
    // Each chart's triangles, counted first: a million-triangle level's charts are some 100 MB,
    // and grown by doubling they would take up to twice that.
    std::vector<size_t> triangleCount(la.chartSlot.size(), 0);
    std::vector<char> counted(la.chartSlot.size(), 0);
    for (uint32_t c : luv.chart) {
        if (!original) ++triangleCount[c];
        if (counted[c]) continue;
        counted[c] = 1;
        const uint32_t source = layoutChartOf(luv, c);
        if (!own && c >= ch.chartCount) triangleCount[c] += 1;
        else if (source < ch.chartCount) triangleCount[c] += L.chartFaces[source].size();
    }
    std::vector<AtlasChart> charts;
    for (size_t t = 0; t < luv.chart.size(); ++t) {
        uint32_t c = luv.chart[t];
        if (la.chartSlot[c] < 0) {
            la.chartSlot[c] = int(charts.size());
            AtlasChart a;
            a.triangles.reserve(triangleCount[c]);
            a.points.reserve(3 * triangleCount[c]);
            a.uvArea = levelChartArea(L, luv, c);
            a.inPlace = !own && c < L.inPlaceCharts;
            // A layout chart's footprint includes its original faces: the layout bake reads them,
            // and around a projected level's triangles they keep the chart's own texels between it
            // and its neighbours, which mips far below the page's gutter blend. A chart grown
            // from islands is just its level triangles, added below.
            const uint32_t source = layoutChartOf(luv, c);
            if (!own && c >= ch.chartCount) {  // an island: its one triangle
                const LayoutIsland& isl = ch.islands[c - ch.chartCount];
                a.points.assign(isl.uv.begin(), isl.uv.end());
                a.triangles.push_back(isl.uv);
            } else if (source < ch.chartCount) {
                for (uint32_t f : L.chartFaces[source]) {
                    for (const Vec2& p : ch.cornerUV[f]) a.points.push_back(p);
                    a.triangles.push_back(ch.cornerUV[f]);
                }
            }
            charts.push_back(std::move(a));
        }
        if (!original) {
            AtlasChart& a = charts[size_t(la.chartSlot[c])];
            std::array<Vec2, 3> tri;
            for (size_t j = 0; j < 3; ++j) tri[j] = luv.uv[t][j];
            a.points.insert(a.points.end(), tri.begin(), tri.end());
            a.triangles.push_back(tri);
        }
    }
    la.charts = charts.size();
    return charts;
}

}  // namespace

LevelAtlas packLevelAtlas(const LayoutData& L, const LevelUVs& luv, bool original, const AtlasOptions& ao) {
    LevelAtlas la;
    la.atlas = packAtlas(levelAtlasCharts(L, luv, original, la), ao);
    return la;
}

namespace {

// A level page whose limit's page is estimated above this many times the finer page starts its
// search at the finer page's size (packLevelPage).
constexpr double kCappedStart = 4;

// The texels of the finer level's page (the request's cap).
double finerTexels(const PageRequest& request) { return double((*request.finerPage)[0]) * (*request.finerPage)[1]; }

// Mips a renderer reaches at a page side: up to options.maxMips, down to minMipSide.
int mipsOfSide(int side, const PackOptions& options) {
    const int limit = side > options.minMipSide ? int(std::floor(std::log2(double(side) / options.minMipSide))) : 0;
    return std::min(options.maxMips, limit);
}

// Grows the page's sides to at least `sides` (empty texels past the charts; placements are
// in texels): a page with wider gutters is never smaller than the coarser levels' cap.
void padPage(AtlasResult& a, const std::array<int, 2>& sides) {
    const int w = std::max(a.width, sides[0]), h = std::max(a.height, sides[1]);
    const double keep = double(a.width) * a.height / (double(w) * h);
    a.utilisation *= keep;
    a.boxUtilisation *= keep;
    a.rasterUtilisation *= keep;
    a.footprintUtilisation *= keep;
    a.width = w;
    a.height = h;
}

// The page of `candidate` grown to the cap page, if it keeps `minDensity` and, below LOD0, the
// finer level's texels.
bool keepsPage(LevelAtlas& candidate, const PageRequest& request, const std::array<int, 2>& capPage, double minDensity) {
    if (candidate.atlas.texelsPerUnit < minDensity * (1 - 1e-9)) return false;
    padPage(candidate.atlas, capPage);
    return !request.finerPage || double(candidate.atlas.width) * candidate.atlas.height <= finerTexels(request);
}

// The same charts for packAtlas: every point, triangle and figure equal, in the same order.
bool sameCharts(const std::vector<AtlasChart>& a, const std::vector<AtlasChart>& b) {
    auto samePoint = [](Vec2 p, Vec2 q) { return p.x == q.x && p.y == q.y; };
    auto sameTriangle = [&](const std::array<Vec2, 3>& p, const std::array<Vec2, 3>& q) {
        return samePoint(p[0], q[0]) && samePoint(p[1], q[1]) && samePoint(p[2], q[2]);
    };
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [&](const AtlasChart& p, const AtlasChart& q) {
        return p.uvArea == q.uvArea && p.inPlace == q.inPlace &&
               std::equal(p.points.begin(), p.points.end(), q.points.begin(), q.points.end(), samePoint) &&
               std::equal(p.triangles.begin(), p.triangles.end(), q.triangles.begin(), q.triangles.end(), sameTriangle);
    });
}

// The same options but (perhaps) the gutter and the thread count, which leaves the page the same.
// A page packed with options `a` serves options `b`: the densest page serves any minimum density
// (AtlasOptions::minTexelsPerUnit), one that may have stopped short only the same minimum.
bool sameButGutter(const AtlasOptions& a, const AtlasOptions& b) {
    return a.maxTexelsPerUnit == b.maxTexelsPerUnit && a.maxSize == b.maxSize && a.powerOfTwo == b.powerOfTwo &&
           a.texelAligned == b.texelAligned && (a.minTexelsPerUnit == 0 || a.minTexelsPerUnit == b.minTexelsPerUnit);
}

// A level's pages, from its charts with or without its original triangles. Each list is built
// once: later pages of it pack the set kept from the first (while it is kept).
struct LevelPages {
    const LayoutData& lay;
    const LevelUVs& luv;
    PackedPages& packed;
    struct Built {
        uint64_t set = 0;
        std::vector<int> chartSlot;
        size_t charts = 0;
    };
    std::array<std::optional<Built>, 2> built{};  // without, with the original triangles

    LevelAtlas pack(bool original, const AtlasOptions& ao) {
        LevelAtlas la;
        std::optional<Built>& b = built[original ? 1 : 0];
        if (b) {
            if (std::optional<AtlasResult> again = packed.packKept(b->set, ao)) {
                la.atlas = std::move(*again);
                la.chartSlot = b->chartSlot;
                la.charts = b->charts;
                return la;
            }
        }
        la.atlas = packed.pack(levelAtlasCharts(lay, luv, original, la), ao);
        b = Built{packed.lastSet(), la.chartSlot, la.charts};
        return la;
    }
};

// A renderer may sample mips below the level's planned range (a small viewport, minification
// along a grazing view): widest gutters first, a page keeps the widest that packs at the same
// density and, below LOD0, within the finer level's texels. A page denser than the finer level's
// (the finer one on the original's texels) trades that excess for the gutter: drawn smaller than
// the finer level, it shows no more of the texture than the finer one does, while its narrower
// gutters, fewer model units wide, blend neighbouring charts at the mips a small view samples.
LevelAtlas widenGutters(const LayoutData& lay, const PageRequest& request, const PackOptions& options, const AtlasOptions& ao,
                        LevelPages& pages, LevelAtlas la) {
    const int mips = std::max(0, int(std::log2(std::max(2, la.atlas.gutter) / 2)));
    const double density = la.atlas.texelsPerUnit;
    const double finer = request.finerDensity && *request.finerDensity > 0 ? *request.finerDensity / lay.uvPerUnit : density;
    const double floor = std::min(density, finer);
    for (int m = mipsOfSide(std::max(la.atlas.width, la.atlas.height), options); m > mips; --m) {
        AtlasOptions wide = ao;
        wide.gutter = 2 << m;
        wide.maxTexelsPerUnit = density;
        // Without a lower floor a candidate below the density is dropped (keepsPage): its search
        // may stop once it is known to fall short.
        if (!(floor < density)) wide.minTexelsPerUnit = density * (1 - 1e-9);
        LevelAtlas candidate = pages.pack(request.originalTriangles, wide);
        const double reached = candidate.atlas.texelsPerUnit;
        const double texels = double(candidate.atlas.width) * candidate.atlas.height;
        bool kept = keepsPage(candidate, request, la.capPage, density);
        if (!kept && floor < density) {
            // The densest page this gutter takes within the finer level's texels, down to its density.
            double d = std::min(density, reached);
            if (request.finerPage && texels > finerTexels(request)) d *= std::sqrt(finerTexels(request) / texels) * 0.98;
            wide.maxTexelsPerUnit = std::max(d, floor);
            candidate = pages.pack(request.originalTriangles, wide);
            kept = keepsPage(candidate, request, la.capPage, floor);
        }
        if (!kept) continue;
        candidate.capPage = la.capPage;
        return candidate;
    }
    return la;
}

}  // namespace

AtlasResult PackedPages::pack(std::vector<AtlasChart> charts, const AtlasOptions& ao) {
    auto set = std::find_if(sets_.begin(), sets_.end(), [&](const ChartSet& c) { return sameCharts(c.charts, charts); });
    if (set == sets_.end()) {
        if (sets_.size() == kKeptChartSets) sets_.erase(sets_.begin());
        sets_.push_back({nextId_++, std::move(charts), {}, {}});
    } else {
        std::rotate(set, set + 1, sets_.end());
    }
    return packSet(sets_.back(), ao);
}

std::optional<AtlasResult> PackedPages::packKept(uint64_t id, const AtlasOptions& ao) {
    auto set = std::find_if(sets_.begin(), sets_.end(), [&](const ChartSet& c) { return c.id == id; });
    if (set == sets_.end()) return std::nullopt;
    std::rotate(set, set + 1, sets_.end());
    return packSet(sets_.back(), ao);
}

AtlasResult PackedPages::packSet(ChartSet& c, const AtlasOptions& ao) {
    std::vector<ChartFrame>& frames = c.frames[ao.texelAligned ? 1 : 0];
    if (frames.size() != c.charts.size()) frames = chartFrames(c.charts, ao);
    const int start = ao.texelAligned ? ao.gutter : atlasStartGutter(c.charts, ao, &frames);
    for (const Page& p : c.pages)
        if (sameButGutter(p.ao, ao) && (p.ao.gutter == ao.gutter || (!ao.texelAligned && p.start == start))) return p.atlas;
    c.pages.push_back({ao, start, packAtlas(c.charts, ao, &frames)});
    return c.pages.back().atlas;
}

void PackedPages::forgetLarge() {
    auto large = [](const ChartSet& s) {
        size_t corners = 0;
        for (const AtlasChart& c : s.charts) corners += c.points.size() + 3 * c.triangles.size();
        return corners > kKeptCorners;
    };
    sets_.erase(std::remove_if(sets_.begin(), sets_.end(), large), sets_.end());
}

LevelAtlas packLevelPage(const LayoutData& lay, const LevelUVs& luv, const PageRequest& request, const PackOptions& options,
                         PackedPages* shared) {
    const double tMax = request.sourceTexels ? 1.0 : request.texelLimit / lay.uvPerUnit;
    // At density d (layout units) the smallest coverage samples mip log2(d / (tMax x cov / maxCov)).
    const double minCoverageRatio = std::max(request.coverage, 1e-12) / request.maxCoverage;
    auto mipsAt = [&](double d) { return int(std::ceil(std::log2(std::max(1.0, d / (tMax * minCoverageRatio)) - 1e-9))); };
    int mips = mipsAt(tMax);
    double usedUv = 0;
    {
        std::vector<char> seen(luv.ownChartArea.empty() ? lay.chartUvArea.size() : luv.ownChartArea.size(), 0);
        for (uint32_t c : luv.chart)
            if (!seen[c]) { seen[c] = 1; usedUv += levelChartArea(lay, luv, c); }
    }
    double side = std::min(double(options.maxSize), std::sqrt(usedUv) * tMax / kPageSideFill);
    int mipLimit = side > options.minMipSide ? int(std::floor(std::log2(side / options.minMipSide))) : 0;
    mips = std::clamp(mips, 0, std::min(options.maxMips, mipLimit));
    AtlasOptions ao;
    ao.maxTexelsPerUnit = tMax;
    ao.gutter = 2 << mips;
    ao.maxSize = options.maxSize;
    ao.powerOfTwo = options.powerOfTwo;
    ao.threads = options.threads;
    ao.texelAligned = request.sourceTexels;
    // Below LOD0 the page holds no more texels than the finer level's. When the limit's page
    // (estimated from the charts' coverage) fits the page cap but is many times the finer page,
    // the search may start at the density the estimate fits into the finer page
    // (request.startNearCap): the loop below would otherwise pack that large page only to shrink
    // it. The gutter stays the limit's.
    const bool capped = request.startNearCap && request.finerPage && !request.sourceTexels &&
                        std::sqrt(usedUv) * tMax / kPageSideFill < options.maxSize &&
                        usedUv * std::pow(tMax / kPageSideFill, 2) > kCappedStart * finerTexels(request);
    if (capped) ao.maxTexelsPerUnit = std::sqrt(finerTexels(request) / usedUv) * kPageSideFill;
    PackedPages own;
    LevelPages pages{lay, luv, shared ? *shared : own};
    LevelAtlas la = pages.pack(request.originalTriangles, ao);
    // Narrower gutters when the density fell short of the limit. Not for the source texels: their
    // packer narrows the gutter itself, down to 2 texels, so a narrower start repeats its attempts.
    for (int m = std::clamp(mipsAt(la.atlas.texelsPerUnit), 0, mips); m < mips && !request.sourceTexels && !capped; ++m) {
        AtlasOptions narrow = ao;
        narrow.gutter = 2 << m;
        LevelAtlas denser = pages.pack(request.originalTriangles, narrow);
        if (mipsAt(denser.atlas.texelsPerUnit) > m) continue;
        mips = m;
        ao = narrow;
        la = std::move(denser);
        break;
    }
    for (int tries = 0; request.finerPage && tries < 8; ++tries) {
        double previous = finerTexels(request);
        double now = double(la.atlas.width) * la.atlas.height;
        if (now <= previous) break;
        ao.maxTexelsPerUnit = std::min(ao.maxTexelsPerUnit, la.atlas.texelsPerUnit) * std::sqrt(previous / now) * 0.98;
        la = pages.pack(false, ao);
    }
    la.capPage = {la.atlas.width, la.atlas.height};
    if (request.widenGutters) la = widenGutters(lay, request, options, ao, pages, std::move(la));
    return la;
}

void recordPage(const LevelAtlas& la, const LayoutData& lay, PackLevelReport& r) {
    r.gutter = la.atlas.gutter;
    r.mips = std::max(0, int(std::log2(std::max(2, r.gutter) / 2)));  // the packer may narrow the gutter
    r.width = la.atlas.width;
    r.height = la.atlas.height;
    r.charts = la.charts;
    r.utilisation = la.atlas.utilisation;
    r.boxUtilisation = la.atlas.boxUtilisation;
    r.rasterUtilisation = la.atlas.rasterUtilisation;
    r.footprintUtilisation = la.atlas.footprintUtilisation;
    r.texelsPerUnit = la.atlas.texelsPerUnit * lay.uvPerUnit;
}

}  // namespace lodbake::lod_detail

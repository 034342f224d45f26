// Texture deviation of candidate layouts against a probe bake (rank_choice.h).
//
// Pipeline (driven by chooseLayoutByBake, layout_choice.cpp):
//   probeLayout (cells and samples) -> the probe bake (the caller's) -> per candidate page:
//   textureDeviation (bilinear read-back at the samples) -> chooseCandidate -> choiceReason.
#include "lod/rank_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lodbake::lod_detail {
namespace {

// Channel values of an RGB page at texel coordinates (x, y) (texel centres at integers),
// bilinear with clamped borders, as a renderer's magnification filter reads it.
void bilinear(const std::vector<float>& rgb, int w, int h, double x, double y, double out[3]) {
    x = std::clamp(x, 0.0, double(w - 1));
    y = std::clamp(y, 0.0, double(h - 1));
    const int x0 = std::min(int(x), w - 1), y0 = std::min(int(y), h - 1);
    const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
    const double fx = x - x0, fy = y - y0;
    auto at = [&](int px, int py, int c) { return double(rgb[(size_t(py) * size_t(w) + size_t(px)) * 3 + size_t(c)]); };
    for (int c = 0; c < 3; ++c)
        out[c] = (at(x0, y0, c) * (1 - fx) + at(x1, y0, c) * fx) * (1 - fy) + (at(x0, y1, c) * (1 - fx) + at(x1, y1, c) * fx) * fy;
}

}  // namespace

ProbeLayout probeLayout(const std::vector<std::array<Vec3, 3>>& triangles, const ProbeOptions& options) {
    ProbeLayout p;
    const size_t n = triangles.size();
    if (n == 0) return p;
    const size_t perRowMax = size_t(std::max(1, options.maxSide / options.minCell));
    const size_t stride = (n + perRowMax * perRowMax - 1) / (perRowMax * perRowMax);
    const size_t cells = (n + stride - 1) / stride;
    size_t perRow = size_t(std::ceil(std::sqrt(double(cells))));
    while (perRow * perRow < cells) ++perRow;
    p.cell = std::clamp(options.maxSide / int(perRow), options.minCell, options.maxCell);
    p.side = int(perRow) * p.cell;
    const int c = p.cell;
    const size_t samplesPerCell = size_t(c - 1) * size_t(c) / 2;
    for (size_t i = 0; i < cells; ++i) {
        const uint32_t t = uint32_t(i * stride);
        const int x0 = int(i % perRow) * c, y0 = int(i / perRow) * c;
        p.triangles.push_back(t);
        const double s = 1.0 / p.side;
        p.uv.push_back({Vec2{x0 * s, y0 * s}, Vec2{(x0 + c) * s, y0 * s}, Vec2{x0 * s, (y0 + c) * s}});
        // The cell's samples stand for the 3D area of the triangles it covers (its stride group).
        double group = 0;
        for (size_t u = t; u < std::min(n, size_t(t) + stride); ++u) group += triangleArea(triangles[u][0], triangles[u][1], triangles[u][2]);
        if (!(group > 0)) continue;
        const double weight = group / double(samplesPerCell);
        for (int j = 0; j + 2 <= c; ++j)
            for (int k = 0; k + j + 2 <= c; ++k) {
                const double a = (k + 0.5) / c, b = (j + 0.5) / c;  // along the +x and +y legs
                ProbeLayout::Sample smp;
                smp.triangle = t;
                smp.bary = {1 - a - b, a, b};
                smp.texel = uint32_t((y0 + j) * p.side + x0 + k);
                smp.weight = weight;
                p.samples.push_back(smp);
            }
    }
    return p;
}

BakeTarget objectSpaceTarget(std::vector<std::array<Vec2, 3>> uv) {
    BakeTarget t;
    t.normal.assign(uv.size(), {Vec3{0, 0, 1}, Vec3{0, 0, 1}, Vec3{0, 0, 1}});
    t.tangent.assign(uv.size(), {Vec4{1, 0, 0, 1}, Vec4{1, 0, 0, 1}, Vec4{1, 0, 0, 1}});
    t.uv = std::move(uv);
    return t;
}

TextureDeviation textureDeviation(const ProbeLayout& probe, const PageChannels& probePage, const PageChannels& page,
                                  const std::vector<std::array<Vec2, 3>>& pageUV) {
    TextureDeviation d;
    const bool normal = probePage.normal && page.normal && !probePage.normal->empty() && !page.normal->empty();
    double sumColor = 0, sumNormal = 0, total = 0;
    for (const ProbeLayout::Sample& s : probe.samples) {
        const std::array<Vec2, 3>& t = pageUV[s.triangle];
        const Vec2 uv = t[0] * s.bary[0] + t[1] * s.bary[1] + t[2] * s.bary[2];
        const double x = uv.x * page.width - 0.5, y = uv.y * page.height - 0.5;
        double v[3];
        bilinear(*page.color, page.width, page.height, x, y, v);
        for (int c = 0; c < 3; ++c) {
            const double e = v[c] - (*probePage.color)[size_t(s.texel) * 3 + size_t(c)];
            sumColor += s.weight * e * e;
        }
        if (normal) {
            bilinear(*page.normal, page.width, page.height, x, y, v);
            for (int c = 0; c < 3; ++c) {
                const double e = v[c] - (*probePage.normal)[size_t(s.texel) * 3 + size_t(c)];
                sumNormal += s.weight * e * e;
            }
        }
        total += s.weight;
    }
    if (!(total > 0)) return d;
    const double mseColor = sumColor / (3 * total), mseNormal = sumNormal / (3 * total);
    d.color = std::sqrt(mseColor);
    d.normal = std::sqrt(mseNormal);
    d.score = normal ? std::sqrt(0.5 * (mseColor + mseNormal)) : d.color;
    return d;
}

size_t bestCandidate(const std::vector<RankCandidate>& candidates) {
    size_t best = 0;
    for (size_t i = 1; i < candidates.size(); ++i)
        if (candidates[i].deviation.score < candidates[best].deviation.score) best = i;
    return best;
}

size_t chooseCandidate(const std::vector<RankCandidate>& candidates, uint32_t byEnergy, double margin) {
    const size_t best = bestCandidate(candidates);
    for (size_t i = 0; i < candidates.size(); ++i)
        if (candidates[i].rank == byEnergy && candidates[i].deviation.score <= candidates[best].deviation.score * (1 + margin))
            return i;
    return best;
}

std::string choiceReason(const std::vector<RankCandidate>& candidates, size_t chosen, uint32_t byEnergy) {
    auto name = [](uint32_t rank) { return rank == 0 ? std::string("T0") : "rank " + std::to_string(rank); };
    const RankCandidate& c = candidates[chosen];
    const RankCandidate* runnerUp = nullptr;
    for (const RankCandidate& o : candidates)
        if (&o != &c && (!runnerUp || o.deviation.score < runnerUp->deviation.score)) runnerUp = &o;
    char buf[256];
    if (!runnerUp) return name(c.rank) + ": the only candidate";
    if (runnerUp->deviation.score < c.deviation.score) {  // kept within the margin
        std::snprintf(buf, sizeof buf, "%s, the energy rule's pick, scores within the margin of the least texture deviation "
                      "(%.5f; %s %.5f)", name(c.rank).c_str(), c.deviation.score, name(runnerUp->rank).c_str(),
                      runnerUp->deviation.score);
        return buf;
    }
    std::snprintf(buf, sizeof buf, "%s shows the least texture deviation (%.5f; next %s %.5f)", name(c.rank).c_str(),
                  c.deviation.score, name(runnerUp->rank).c_str(), runnerUp->deviation.score);
    std::string why = buf;
    why += c.rank == byEnergy ? "; also the energy rule's pick" : "; the energy rule would pick " + name(byEnergy);
    return why;
}

}  // namespace lodbake::lod_detail

// Stretch metrics of the chart maps (stretch_metrics.h). Reference: P. Sander, J. Snyder,
// S. Gortler, H. Hoppe, "Texture mapping progressive meshes" (SIGGRAPH 2001), the L2 and Linf
// stretch of the map UV -> 3D.
#include "param/stretch_metrics.h"

#include <algorithm>
#include <cmath>

#include "lodbake/core/math.h"

namespace lodbake::param_detail {
namespace {

struct Stretch {
    double l2 = 0, linf = 0;
    std::vector<double> ratios;  // per triangle UV area / 3D area (raw), 3D-degenerate skipped
    double sumUV = 0, sum3D = 0;
};

// Sander et al. 2001 stretch of the map UV -> 3D, accumulated (not yet normalised).
void accumulateStretch(const ChartMesh& m, const std::vector<Vec2>& uv, Stretch& s, double& l2sum, double& gmax) {
    for (const Tri& t : m.triangles) {
        Vec3 q1 = m.positions[t[0]], q2 = m.positions[t[1]], q3 = m.positions[t[2]];
        Vec2 p1 = uv[t[0]], p2 = uv[t[1]], p3 = uv[t[2]];
        double a3 = triangleArea(q1, q2, q3);
        double a2 = signedArea(p1, p2, p3);
        s.sumUV += std::max(a2, 0.0);
        s.sum3D += a3;
        if (a3 <= 0 || a2 <= 0) continue;
        s.ratios.push_back(a2 / a3);
        Vec3 Ss = (q1 * (p2.y - p3.y) + q2 * (p3.y - p1.y) + q3 * (p1.y - p2.y)) / (2 * a2);
        Vec3 St = (q1 * (p3.x - p2.x) + q2 * (p1.x - p3.x) + q3 * (p2.x - p1.x)) / (2 * a2);
        double a = dot(Ss, Ss), b = dot(Ss, St), c = dot(St, St);
        l2sum += (a + c) / 2 * a3;
        gmax = std::max(gmax, std::sqrt(std::max(0.0, ((a + c) + std::sqrt((a - c) * (a - c) + 4 * b * b)) / 2)));
    }
}

void finishStretch(Stretch& s, double l2sum, double gmax) {
    double norm = s.sum3D > 0 ? std::sqrt(s.sumUV / s.sum3D) : 1;
    s.l2 = s.sum3D > 0 ? std::sqrt(l2sum / s.sum3D) * norm : 0;
    s.linf = gmax * norm;
}

double ratioStdDev(const std::vector<double>& ratios, double mean) {
    if (ratios.empty() || !(mean > 0)) return 0;
    double acc = 0;
    for (double r : ratios) acc += (r / mean - 1) * (r / mean - 1);
    return std::sqrt(acc / double(ratios.size()));
}

}  // namespace

double measureCharts(const std::vector<LocalChart>& charts, ParameterizeResult& res) {
    Stretch all;
    double allL2 = 0, allG = 0;
    for (size_t c = 0; c < charts.size(); ++c) {
        Stretch s;
        double l2 = 0, g = 0;
        accumulateStretch(charts[c].mesh, charts[c].uv, s, l2, g);
        finishStretch(s, l2, g);
        ChartReport& rep = res.chartReports[c];
        rep.stretchL2 = s.l2;
        rep.stretchLinf = s.linf;
        rep.areaRatioStdDev = ratioStdDev(s.ratios, s.sum3D > 0 ? s.sumUV / s.sum3D : 0);
        accumulateStretch(charts[c].mesh, charts[c].uv, all, allL2, allG);
    }
    finishStretch(all, allL2, allG);
    res.stretchL2 = all.l2;
    res.stretchLinf = all.linf;
    double meanRatio = all.sum3D > 0 ? all.sumUV / all.sum3D : 0;
    res.areaRatioStdDev = ratioStdDev(all.ratios, meanRatio);
    for (double r : all.ratios) {
        int bin = std::clamp(int(r / meanRatio / 0.2), 0, 9);
        ++res.areaRatioHistogram[size_t(bin)];
    }
    return all.sumUV;
}

}  // namespace lodbake::param_detail

// Ceres bridge: minimises E = beta E_pixel + (1 - beta) E_poly over a chart's UVs (thesis 3.3.2;
// Maillot et al. 1993 for E_l / E_s). The only translation unit that includes Ceres.
//
// Every term is a small analytic cost function (residual = sqrt(weight) x the term's root); the
// area residual refuses to evaluate (returns false) when a triangle's UV determinant is <= 0, so
// the trust-region step that would fold it is rejected and the map stays locally injective.
// Coordinates are scaled by 1/sqrt(3D area) for conditioning; every term is scale-free.
#include <algorithm>
#include <cmath>
#include <mutex>

#include <SuiteSparse_config.h>
#include <ceres/ceres.h>
#include <glog/logging.h>

#include "lodbake/core/errors.h"
#include "lodbake/param/chart_uv.h"
#include "param/chart_energy_terms.h"
#include "param/solver_output.h"
#include "param/solver_threads.h"
#include "param/sparse_solver.h"

namespace lodbake {
namespace {

using param_detail::EnergyTerms;

// Weight of the sliver barriers (AreaCost, guarded LevelCost); zero above kBarrier x 3D area.
constexpr double kBarrierWeight = 0.1;

// A level triangle is guarded (barrier, kept positive) when its UV det exceeds this fraction of
// its 3D area at the round's start: the barrier's residual stays finite (below 2e7) there.
constexpr double kGuardMargin = 1e-9;

// r = s (|v_i - v_j|^2 - L2) / L2
class EdgeCost final : public ceres::SizedCostFunction<1, 2, 2> {
public:
    EdgeCost(double s, double l2) : s_(s), l2_(l2) {}
    bool Evaluate(double const* const* p, double* r, double** J) const override {
        double dx = p[0][0] - p[1][0], dy = p[0][1] - p[1][1];
        r[0] = s_ * (dx * dx + dy * dy - l2_) / l2_;
        double g = 2 * s_ / l2_;
        if (J) {
            if (J[0]) { J[0][0] = g * dx; J[0][1] = g * dy; }
            if (J[1]) { J[1][0] = -g * dx; J[1][1] = -g * dy; }
        }
        return true;
    }

private:
    double s_, l2_;
};

// r = s (det(v_j - v_i, v_k - v_i) - A2) / A2; infeasible when det <= 0.
class AreaCost final : public ceres::SizedCostFunction<2, 2, 2, 2> {
public:
    AreaCost(double s, double b, double a2) : s_(s), a2_(a2), b_(b) {}
    bool Evaluate(double const* const* p, double* r, double** J) const override {
        double e1x = p[1][0] - p[0][0], e1y = p[1][1] - p[0][1];
        double e2x = p[2][0] - p[0][0], e2y = p[2][1] - p[0][1];
        double det = e1x * e2y - e1y * e2x;
        if (!(det > 0)) return false;
        r[0] = s_ * (det - a2_) / a2_;
        double g = s_ / a2_;
        // Barrier below kBarrier a2: the Maillot terms are bounded as det -> 0+, so without it a
        // non-developable chart can settle on slivers whose float UVs flip (thesis 3.3.2 asks
        // for an injective map, not a barely-injective one).
        if (det < kBarrier * a2_) {
            r[1] = b_ * (kBarrier * a2_ / det - 1);
        } else {
            r[1] = 0;
        }
        double gb = det < kBarrier * a2_ ? -b_ * kBarrier * a2_ / (det * det) : 0;
        if (J) {
            // d det / d v_j = (e2y, -e2x), d det / d v_k = (-e1y, e1x), d det / d v_i = -(sum).
            // Row-major 2 x 2 per block: row 0 = area residual, row 1 = barrier.
            const double dB[2] = {e2y, -e2x}, dC[2] = {-e1y, e1x}, dA[2] = {-(e2y - e1y), -(e1x - e2x)};
            double* Js[3] = {J[0], J[1], J[2]};
            const double* dd[3] = {dA, dB, dC};
            for (int b = 0; b < 3; ++b)
                if (Js[b])
                    for (int d = 0; d < 2; ++d) {
                        Js[b][d] = g * dd[b][d];
                        Js[b][2 + d] = gb * dd[b][d];
                    }
        }
        return true;
    }
    static constexpr double kBarrier = 0.02;

private:
    double s_, a2_, b_;
};

// r = s sum_b c_b v_b (linear), over distinct parameter blocks.
class PolyCost final : public ceres::CostFunction {
public:
    PolyCost(double s, std::vector<double> coef) : s_(s), coef_(std::move(coef)) {
        set_num_residuals(2);
        for (size_t i = 0; i < coef_.size(); ++i) mutable_parameter_block_sizes()->push_back(2);
    }
    bool Evaluate(double const* const* p, double* r, double** J) const override {
        r[0] = r[1] = 0;
        for (size_t b = 0; b < coef_.size(); ++b) {
            r[0] += s_ * coef_[b] * p[b][0];
            r[1] += s_ * coef_[b] * p[b][1];
        }
        if (J)
            for (size_t b = 0; b < coef_.size(); ++b)
                if (J[b]) {
                    J[b][0] = s_ * coef_[b]; J[b][1] = 0;
                    J[b][2] = 0; J[b][3] = s_ * coef_[b];
                }
        return true;
    }

private:
    double s_;
    std::vector<double> coef_;
};

// A level triangle whose corners are linear combinations of chart vertices. Guard mode: residual 0,
// infeasible when det <= 0. Penalty mode: r = s max(0, delta a2 - det) / a2 (pulls a flipped
// triangle back to positive orientation).
class LevelCost final : public ceres::CostFunction {
public:
    // w[b] = weights of block b in corners A, B, C.
    LevelCost(bool guard, double s, double a2, std::vector<std::array<double, 3>> w)
        : guard_(guard), s_(s), a2_(a2), w_(std::move(w)) {
        set_num_residuals(1);
        for (size_t i = 0; i < w_.size(); ++i) mutable_parameter_block_sizes()->push_back(2);
    }
    bool Evaluate(double const* const* p, double* r, double** J) const override {
        double A[2] = {0, 0}, B[2] = {0, 0}, C[2] = {0, 0};
        for (size_t b = 0; b < w_.size(); ++b)
            for (int d = 0; d < 2; ++d) {
                A[d] += w_[b][0] * p[b][d];
                B[d] += w_[b][1] * p[b][d];
                C[d] += w_[b][2] * p[b][d];
            }
        double e1x = B[0] - A[0], e1y = B[1] - A[1], e2x = C[0] - A[0], e2y = C[1] - A[1];
        double det = e1x * e2y - e1y * e2x;
        if (guard_ && !(det > 0)) return false;
        double h = kDelta * a2_ - det;
        bool active = !guard_ && h > 0;
        // Guard mode: barrier below kBarrier a2 (keeps guarded level triangles away from slivers).
        bool barrier = guard_ && det < kBarrier * a2_;
        r[0] = active ? s_ * h / a2_ : barrier ? kBarrierWeight * (kBarrier * a2_ / det - 1) : 0;
        if (J) {
            double g = active ? -s_ / a2_ : barrier ? -kBarrierWeight * kBarrier * a2_ / (det * det) : 0;
            double dA[2] = {-e2y + e1y, e2x - e1x}, dB[2] = {e2y, -e2x}, dC[2] = {-e1y, e1x};
            for (size_t b = 0; b < w_.size(); ++b)
                if (J[b])
                    for (int d = 0; d < 2; ++d) J[b][d] = g * (w_[b][0] * dA[d] + w_[b][1] * dB[d] + w_[b][2] * dC[d]);
        }
        return true;
    }
    static constexpr double kDelta = 0.05;
    static constexpr double kBarrier = 0.02;

private:
    bool guard_;
    double s_, a2_;
    std::vector<std::array<double, 3>> w_;
};

double levelDet(const ChartLevelTriangle& t, const std::vector<Vec2>& uv) {
    Vec2 a = chartPointUV(t.corner[0], uv), b = chartPointUV(t.corner[1], uv), c = chartPointUV(t.corner[2], uv);
    return cross(b - a, c - a);
}

}  // namespace

void silenceSolverOutput() {
    static std::once_flag once;
    std::call_once(once, [] {
        // Below FATAL nothing is formatted or written; a FATAL (a Ceres CHECK) still reaches stderr
        // as the process aborts. Not initialising glog also keeps it from opening log files.
        if (!google::IsGoogleLoggingInitialized()) FLAGS_minloglevel = google::GLOG_FATAL;
        SuiteSparse_config.printf_func = nullptr;
    });
}

ChartSolveResult optimizeChartUV(const ChartMesh& chart, const std::vector<ChartPair>& pairs,
                                 const std::vector<Vec2>& initial, const ChartSolveOptions& options) {
    silenceSolverOutput();
    keepSolverThreadsSerial();
    ChartSolveResult res;
    res.uv = initial;
    res.before = chartEnergy(chart, pairs, initial, options.energy);
    res.after = res.before;
    if (options.maxIterations <= 0 || chart.triangles.empty() || countFlips(chart, initial) > 0) return res;

    // Work in coordinates scaled to unit 3D area (all terms are scale-free).
    ChartMesh scaled = chart;
    std::vector<ChartPair> spairs = pairs;
    double area = 0;
    for (const Tri& t : chart.triangles)
        area += triangleArea(chart.positions[t[0]], chart.positions[t[1]], chart.positions[t[2]]);
    double k = area > 0 ? 1 / std::sqrt(area) : 1;
    for (Vec3& p : scaled.positions) p = p * k;
    for (ChartPair& p : spairs) p.deviation *= k;
    EnergyTerms terms = param_detail::buildEnergyTerms(scaled, spairs, options.energy);

    std::vector<double> x(2 * initial.size());
    for (size_t i = 0; i < initial.size(); ++i) {
        x[2 * i] = initial[i].x * k;
        x[2 * i + 1] = initial[i].y * k;
    }
    auto block = [&](uint32_t v) { return x.data() + 2 * size_t(v); };

    const int maxRounds = chart.levelTriangles.empty() ? 1 : std::max(1, options.levelRounds);
    std::vector<Vec2> current = initial;
    res.levelFlipsBefore = countLevelFlips(chart, initial);
    res.levelFlipsAfter = res.levelFlipsBefore;
    for (int round = 0; round < maxRounds; ++round) {
        ceres::Problem problem;
        // Parameter blocks in vertex order (deterministic).
        for (size_t i = 0; i < initial.size(); ++i) problem.AddParameterBlock(block(uint32_t(i)), 2);
        if (terms.edgeWeight > 0)
            for (const auto& e : terms.edges)
                problem.AddResidualBlock(new EdgeCost(std::sqrt(terms.edgeWeight), e.l2), nullptr, block(e.i), block(e.j));
        // Area blocks are always present (weight floor) because they guard against folding.
        double aw = std::sqrt(std::max(terms.areaWeight, 1e-9));
        for (const auto& t : terms.tris)
            problem.AddResidualBlock(new AreaCost(aw, kBarrierWeight, t.a2), nullptr, block(t.v[0]), block(t.v[1]), block(t.v[2]));
        if (terms.polyWeight > 0)
            for (const auto& p : terms.pairs) {
                std::vector<uint32_t> verts{p.pair.vertex};
                std::vector<double> coef{1.0};
                for (int c = 0; c < 3; ++c) {
                    if (p.pair.bary[c] == 0) continue;
                    auto it = std::find(verts.begin(), verts.end(), p.pair.coarse[c]);
                    if (it == verts.end()) {
                        verts.push_back(p.pair.coarse[c]);
                        coef.push_back(-p.pair.bary[c]);
                    } else {
                        coef[size_t(it - verts.begin())] -= p.pair.bary[c];
                    }
                }
                std::vector<double*> blocks;
                for (uint32_t v : verts) blocks.push_back(block(v));
                problem.AddResidualBlock(new PolyCost(std::sqrt(terms.polyWeight) / p.dev, coef), nullptr, blocks);
            }
        // Level triangles: guard the positive ones, pull the flipped ones back.
        size_t penalties = 0;
        for (const ChartLevelTriangle& t : chart.levelTriangles) {
            std::vector<uint32_t> verts;
            std::vector<std::array<double, 3>> w;
            for (int c = 0; c < 3; ++c)
                for (int k = 0; k < 3; ++k) {
                    double wk = t.corner[size_t(c)].weight[size_t(k)];
                    if (wk == 0) continue;
                    uint32_t v = t.corner[size_t(c)].vertex[size_t(k)];
                    auto it = std::find(verts.begin(), verts.end(), v);
                    size_t b = size_t(it - verts.begin());
                    if (it == verts.end()) {
                        verts.push_back(v);
                        w.push_back({0, 0, 0});
                    }
                    w[b][size_t(c)] += wk;
                }
            if (verts.size() < 3) continue;
            // Guarded only with a margin the barrier can take: a level triangle that starts a
            // sliver (det a tiny fraction of its area, or rounded to zero in the scaled frame)
            // would make the barrier's first residual infinite and Ceres would stop before its
            // first step; it is pulled back like a flipped one instead. A triangle without 3D
            // area has nothing to pull towards once flat.
            const double a2 = t.area2 * k * k;
            const double det = levelDet(t, current) * k * k;
            bool guard = det > kGuardMargin * a2;
            if (!guard && !(a2 > 0)) continue;
            if (!guard) ++penalties;
            std::vector<double*> blocks;
            for (uint32_t v : verts) blocks.push_back(block(v));
            problem.AddResidualBlock(new LevelCost(guard, std::sqrt(10.0), a2, w), nullptr, blocks);
        }

        ceres::Solver::Options so;
        so.minimizer_type = ceres::TRUST_REGION;
        so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
        // The Jacobian is very sparse (a residual touches at most a few vertices): sparse
        // Cholesky of the normal equations for small charts; a dense QR of a few hundred unknowns
        // already costs more than the whole rest of parameterize. Large charts take conjugate
        // gradients on the normal equations (Jacobi-preconditioned, a bounded number of steps):
        // the pairs and level triangles couple far-apart vertices, so the Cholesky factor fills
        // in, and its memory and time grow far faster than the chart (docs/benchmarks.md).
        so.max_num_iterations = options.maxIterations;
        if (initial.size() > kLargeChartVertices) {
            so.linear_solver_type = ceres::CGNR;
            so.preconditioner_type = ceres::JACOBI;
            so.max_linear_solver_iterations = 50;
            so.max_num_iterations = std::min(options.maxIterations, kLargeChartIterations);
        } else {
            chooseSparseSolver(so, x.size(), 200);
        }
        so.num_threads = 1;
        so.logging_type = ceres::SILENT;
        so.minimizer_progress_to_stdout = false;
        so.function_tolerance = 1e-4;  // stop once an iteration lowers E by less than 0.01%
        ceres::Solver::Summary summary;
        ceres::Solve(so, &problem, &summary);
        res.iterations += int(summary.iterations.size());

        if (summary.termination_type == ceres::FAILURE || !std::isfinite(summary.final_cost)) break;
        std::vector<Vec2> uv(initial.size());
        for (size_t i = 0; i < uv.size(); ++i) uv[i] = {x[2 * i] / k, x[2 * i + 1] / k};
        ChartEnergy after = chartEnergy(chart, pairs, uv, options.energy);
        size_t levelFlips = countLevelFlips(chart, uv);
        bool better = levelFlips < res.levelFlipsAfter || (levelFlips == res.levelFlipsAfter && after.E < res.after.E);
        if (std::isfinite(after.E) && better && countFlips(chart, uv) == 0) {
            res.uv = uv;
            res.after = after;
            res.levelFlipsAfter = levelFlips;
            res.improved = true;
        }
        current = uv;
        if (penalties == 0 || levelFlips == 0) break;
    }
    return res;
}

}  // namespace lodbake

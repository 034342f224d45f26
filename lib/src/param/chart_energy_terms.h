// Private: the energy terms of one chart with their denominators clamped, shared by the evaluator
// (chart_uv.cpp) and the Ceres bridge (ceres_energy.cpp) so both compute the same E.
#pragma once

#include <vector>

#include "lodbake/param/chart_uv.h"

namespace lodbake::param_detail {

struct EdgeTerm {
    uint32_t i, j;
    double l2;  // |V_i - V_j|^2 (clamped below)
};
struct TriTerm {
    Tri v;
    double a2;  // |(V_j - V_i) x (V_k - V_i)| (clamped below)
};
struct PairTerm {
    ChartPair pair;
    double dev;  // clamped deviation
};

// E = edgeWeight sum r_e^2 + areaWeight sum r_t^2 + polyWeight sum |r_p|^2 / dev^2 where
// r_e = (|v_i-v_j|^2 - l2)/l2, r_t = (det - a2)/a2, r_p = v_i - sum_k alpha_k v_k.
struct EnergyTerms {
    std::vector<EdgeTerm> edges;
    std::vector<TriTerm> tris;
    std::vector<PairTerm> pairs;
    double edgeWeight = 0, areaWeight = 0, polyWeight = 0;
    double area3D = 0;
};

EnergyTerms buildEnergyTerms(const ChartMesh& chart, const std::vector<ChartPair>& pairs, const ChartEnergyOptions& o);

}  // namespace lodbake::param_detail

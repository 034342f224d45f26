// Geometric distance between two triangle surfaces: two-sided Hausdorff, mean and RMS surface
// distance from dense, deterministic, area-weighted sampling (Metro-style; Cignoni et al. 1998,
// "Metro: measuring error on simplified surfaces").
//
// The nearest-point queries use CGAL's AABB_tree; CGAL stays inside lib/src/metrics/cgal_distance.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

struct DistanceOptions {
    // Area-weighted samples drawn on each surface (each side). Every referenced vertex of the
    // sampled mesh is also queried (it only contributes to the maximum). 0 = vertices only.
    size_t samplesPerSide = 200000;
    // Deterministic sampling: stratified over the cumulative area with this offset seed. The same
    // inputs and options always give the same figures, whatever `threads` is.
    uint64_t seed = 1;
    // Worker threads for the queries; 0 = all cores. Never changes the result.
    int threads = 0;
    // Coarse to fine, for a maximum wanted fast: when > 1, a first pass queries every
    // refineStride-th area sample, then the vertices that no coarse sample near them bounds below
    // the coarse maximum (d(c) + |v - c|); then every sample is queried only in the runs of
    // kRefineBlock consecutive samples (neighbours on the surface) whose coarse maximum reaches
    // refineFraction x max(the coarse maximum, refineFloor), and there only where the run's strided
    // samples do not already bound the distance below max(the coarse maximum, refineFloor). The
    // maximum is the dense one wherever the worst regions show in the coarse pass and it reaches
    // refineFloor (below the floor it may be less); mean and RMS come from the coarse samples;
    // `samples` counts the queries.
    // 1 = every sample queried (the exact figures of the sampling).
    size_t refineStride = 1;
    double refineFraction = 0.5;
    // A maximum already known to be reached (e.g. another pose's): runs below refineFraction of it
    // are not refined, samples that cannot reach it are not queried. surfaceDistance's second side also takes the first side's maximum.
    double refineFloor = 0;
    // A bound the caller only compares the Hausdorff distance with: measuring stops as soon as a
    // distance above it is found (GeometricDistance::stopped). The figures are then partial; only
    // hausdorff > stopAbove holds. Measuring stops exactly when the full figures' hausdorff would
    // exceed stopAbove, so an unstopped measure's figures are the full ones, whatever `threads` is.
    double stopAbove = std::numeric_limits<double>::infinity();
};
constexpr size_t kRefineBlock = 256;  // samples per refinement run

// Distances measured from the samples of one surface to the other surface (model units).
struct OneSidedDistance {
    double max = 0;   // Hausdorff (one-sided), over area samples and vertices
    double mean = 0;  // area-weighted mean over area samples
    double rms = 0;   // area-weighted root-mean-square over area samples
    size_t samples = 0;  // area samples + vertices queried
};

struct GeometricDistance {
    OneSidedDistance aToB;  // samples on A, nearest points on B
    OneSidedDistance bToA;
    double hausdorff = 0;   // max(aToB.max, bToA.max)
    double mean = 0;        // mean of the two one-sided means
    double rms = 0;         // sqrt of the mean of the two one-sided mean squares
    double diagonal = 0;    // A's bounding-box diagonal (the unit of the relative figures)
    double relHausdorff = 0, relMean = 0, relRms = 0;  // absolute / diagonal (0 if diagonal == 0)
    bool stopped = false;   // a distance above DistanceOptions::stopAbove was found: figures partial
};

// \pre a and b each have at least one triangle with non-zero area.
// \throw Impossible when a mesh has no non-degenerate triangle.
GeometricDistance surfaceDistance(const TriMesh& a, const TriMesh& b, const DistanceOptions& options = {});

// Surface `a` of surfaceDistance prepared once (its sampled triangles and nearest-point tree) to
// measure many surfaces against it: the figures are surfaceDistance(a, b)'s exactly.
class DistanceReference {
public:
    // \throw Impossible when `a` has no non-degenerate triangle. `threads` prepare it (0 = all
    // cores; never changes a figure).
    explicit DistanceReference(const TriMesh& a, int threads = 1);
    ~DistanceReference();
    DistanceReference(DistanceReference&&) noexcept;
    DistanceReference& operator=(DistanceReference&&) noexcept;

    // The closest point of `a`'s surface to p (thread-safe).
    Vec3 closestPoint(Vec3 p) const;
    // The closest point of `a`'s surface to each of `points`, on `threads` threads (0 = all cores;
    // never changes the result). Consecutive points that lie close together (samples along a
    // surface) start their search from the previous answer: far cheaper than one closestPoint each.
    // near[i], when given and not NaN, is a point of the surface near points[i] (an earlier
    // answer for a point close by): it bounds the search, never changing the answer.
    std::vector<Vec3> closestPoints(const std::vector<Vec3>& points, int threads = 0, const std::vector<Vec3>& near = {}) const;

    struct Prepared;
    const Prepared& prepared() const { return *prepared_; }

private:
    std::unique_ptr<Prepared> prepared_;
};

// \throw Impossible when b has no non-degenerate triangle.
GeometricDistance surfaceDistance(const DistanceReference& a, const TriMesh& b, const DistanceOptions& options = {});

}  // namespace lodbake

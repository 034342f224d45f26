// The M-AGSphere's view of the input mesh: the sphere's frame, face normals and their finest
// cells, half-edge twins and vertex fans (from core/adjacency.h).
#include "agsphere/topology.h"

#include <cmath>

namespace lodbake::agsphere_detail {
namespace {

// Rotation taking unit a onto unit b (Rodrigues), as a Frame.
Frame rotationOnto(Vec3 a, Vec3 b) {
    Frame f;
    Vec3 k = cross(a, b);
    double s = length(k), c = dot(a, b);
    if (s < 1e-12) {
        if (c < 0) {  // half turn about an axis orthogonal to a
            Vec3 axis = normalize(cross(a, std::fabs(a.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
            f.r0 = axis * (2 * axis.x) - Vec3{1, 0, 0};
            f.r1 = axis * (2 * axis.y) - Vec3{0, 1, 0};
            f.r2 = axis * (2 * axis.z) - Vec3{0, 0, 1};
        }
        return f;
    }
    // R = I + [k]x + [k]x^2 (1 - c) / s^2.
    double m[3][3] = {{0, -k.z, k.y}, {k.z, 0, -k.x}, {-k.y, k.x, 0}};
    double r[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double m2 = 0;
            for (int q = 0; q < 3; ++q) m2 += m[i][q] * m[q][j];
            r[i][j] = (i == j ? 1.0 : 0.0) + m[i][j] + m2 * (1 - c) / (s * s);
        }
    f.r0 = {r[0][0], r[0][1], r[0][2]};
    f.r1 = {r[1][0], r[1][1], r[1][2]};
    f.r2 = {r[2][0], r[2][1], r[2][2]};
    return f;
}

// Unit normals of the faces with a finite non-zero area; hasNormal marks them.
void computeFaceNormals(Topology& t, std::vector<char>& hasNormal) {
    t.normal.assign(t.nf, Vec3{});
    t.degenerate.assign(t.nf, 0);
    hasNormal.assign(t.nf, 0);
    for (uint32_t f = 0; f < t.nf; ++f) {
        const Tri& tr = t.T(f);
        if (degenerateIndices(tr)) {
            t.degenerate[f] = 1;
            continue;
        }
        Vec3 n = cross(t.P(tr[1]) - t.P(tr[0]), t.P(tr[2]) - t.P(tr[0]));
        double l = length(n);
        if (l > 0 && std::isfinite(l)) {
            t.normal[f] = n / l;
            hasNormal[f] = 1;
        }
    }
}

// Faces without a normal take the normal of a neighbour (breadth-first over twins, from the faces
// in index order); those out of reach get +z.
void spreadMissingNormals(Topology& t, std::vector<char>& hasNormal) {
    std::vector<uint32_t> queue;
    for (uint32_t f = 0; f < t.nf; ++f)
        if (hasNormal[f]) queue.push_back(f);
    for (size_t q = 0; q < queue.size(); ++q) {
        uint32_t f = queue[q];
        for (uint32_t k = 0; k < 3; ++k) {
            uint32_t o = t.twin[3 * f + k];
            if (o >= kNonManifoldEdge) continue;
            uint32_t g = o / 3;
            if (hasNormal[g] || t.degenerate[g]) continue;
            hasNormal[g] = 1;
            t.normal[g] = t.normal[f];
            queue.push_back(g);
        }
    }
    for (uint32_t f = 0; f < t.nf; ++f)
        if (!hasNormal[f]) t.normal[f] = {0, 0, 1};
}

}  // namespace

Frame alignedFrame(const AgsphereOptions& o) {
    if (o.views.empty() && o.lights.empty()) return {};
    Vec3 d = normalize(!o.views.empty() ? o.views[0] : o.lights[0]);
    return rotationOnto(d, normalize(Vec3{1, 1, 1}));
}

Topology buildTopology(const TriMesh& mesh, int maxDepth, const Frame& frame) {
    Topology t;
    t.mesh = &mesh;
    t.frame = frame;
    t.nf = uint32_t(mesh.triangleCount());
    t.nv = uint32_t(mesh.vertexCount());
    t.maxDepth = maxDepth;
    t.diagonal = bounds(mesh).diagonal();
    std::vector<char> hasNormal;
    computeFaceNormals(t, hasNormal);
    t.twin = halfEdgeTwins(mesh.triangles);
    t.vertexFaces = vertexFaces(mesh.triangles, t.nv);
    spreadMissingNormals(t, hasNormal);
    t.finestCell.resize(t.nf);
    for (uint32_t f = 0; f < t.nf; ++f) t.finestCell[f] = sphereCell(frame.toSphere(t.normal[f]), maxDepth);
    return t;
}

}  // namespace lodbake::agsphere_detail

// The outline faces of a mesh seen from a view (the M-AGSphere pins them, and tests new triangles
// against the rasters, to keep the silhouette of a view-dependent level exactly the original's).
//
//   facing        per face: does it face the eye (orthographic: n.d > 0; perspective: n.(e - p) > 0)
//   contour       edges between a front- and a back-facing face, and mesh-border edges
//   raster        the faces facing the eye projected (same projection) into a square raster ->
//                 coverage mask; outline pixels = covered pixels with an uncovered 4-neighbour,
//                 widened by a band
//   outline       contour edges with a sample (every half pixel) on an outline pixel: the ones that
//                 make the projected outline (interior contours, e.g. the folds of a bumpy scan
//                 seen in front of the body, are not kept)
//   protrudes     (per new triangle, later) does it cover a pixel the original leaves uncovered
//                 with its 8 neighbours: a summed-area table rejects most triangles at once, the
//                 rest are scanned row by row
#include "agsphere/contour.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "lodbake/core/adjacency.h"

namespace lodbake {
namespace {

bool facingEye(const OutlineView& v, Vec3 n, Vec3 p0) { return v.perspective ? dot(n, v.eye - p0) > 0 : dot(n, v.d) > 0; }

// Projected coordinates before the raster mapping; false when behind the eye.
bool projectRaw(const OutlineView& v, Vec3 p, double& x, double& y) {
    Vec3 q = p - v.centre;
    if (!v.perspective) {
        x = dot(q, v.u);
        y = dot(q, v.w);
        return true;
    }
    double z = dot(v.eye - p, v.d);
    if (!(z > 0)) return false;
    x = dot(q, v.u) / z;
    y = dot(q, v.w) / z;
    return true;
}

// Calls visit(x, y) for every raster pixel whose centre lies inside or on triangle (a, b, c).
template <class Visit>
void scanTriangle(int G, double ax, double ay, double bx, double by, double cx, double cy, Visit&& visit) {
    double area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (area == 0) return;
    const double s = area > 0 ? 1 : -1;
    int xa = std::max(0, int(std::floor(std::min({ax, bx, cx}))));
    int xb = std::min(G - 1, int(std::ceil(std::max({ax, bx, cx}))));
    int ya = std::max(0, int(std::floor(std::min({ay, by, cy}))));
    int yb = std::min(G - 1, int(std::ceil(std::max({ay, by, cy}))));
    for (int y = ya; y <= yb; ++y)
        for (int x = xa; x <= xb; ++x) {
            double qx = x + 0.5, qy = y + 0.5;
            double e0 = s * ((bx - ax) * (qy - ay) - (by - ay) * (qx - ax));
            double e1 = s * ((cx - bx) * (qy - by) - (cy - by) * (qx - bx));
            double e2 = s * ((ax - cx) * (qy - cy) - (ay - cy) * (qx - cx));
            if (e0 >= 0 && e1 >= 0 && e2 >= 0 && visit(x, y)) return;
        }
}

}  // namespace

bool OutlineView::project(Vec3 p, double& x, double& y) const {
    if (!projectRaw(*this, p, x, y)) return false;
    x = (x - x0) * scale + margin;
    y = (y - y0) * scale + margin;
    return true;
}

bool protrudes(const OutlineFaces& outline, Vec3 a, Vec3 b, Vec3 c) {
    for (const OutlineView& v : outline.views) {
        double ax, ay, bx, by, cx, cy;
        if (!v.project(a, ax, ay) || !v.project(b, bx, by) || !v.project(c, cx, cy)) continue;
        // Nothing outside the triangle's pixel box: no scan (most triangles, far from the outline).
        const size_t S = size_t(v.size) + 1;
        int x0 = std::clamp(int(std::floor(std::min({ax, bx, cx}))), 0, v.size - 1);
        int x1 = std::clamp(int(std::ceil(std::max({ax, bx, cx}))), 0, v.size - 1);
        int y0 = std::clamp(int(std::floor(std::min({ay, by, cy}))), 0, v.size - 1);
        int y1 = std::clamp(int(std::ceil(std::max({ay, by, cy}))), 0, v.size - 1);
        const auto& q = v.outsideSum;
        uint64_t n = uint64_t(q[size_t(y1 + 1) * S + size_t(x1 + 1)]) + q[size_t(y0) * S + size_t(x0)] -
                     q[size_t(y0) * S + size_t(x1 + 1)] - q[size_t(y1 + 1) * S + size_t(x0)];
        if (n == 0) continue;
        // Row by row: the span of pixel centres inside the triangle, summed from the table.
        double area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
        if (area == 0) continue;
        const double sg = area > 0 ? 1 : -1;
        const double ex[3][2] = {{ax, ay}, {bx, by}, {cx, cy}};
        bool out = false;
        for (int y = y0; y <= y1 && !out; ++y) {
            double qy = y + 0.5, lo = x0 + 0.5, hi = x1 + 0.5;
            for (int k = 0; k < 3 && lo <= hi; ++k) {
                const double* p0 = ex[k];
                const double* p1 = ex[(k + 1) % 3];
                // sg * ((p1 - p0) x (q - p0)) >= 0, linear in qx: A qx + B >= 0.
                double A = -sg * (p1[1] - p0[1]);
                double B = sg * ((p1[0] - p0[0]) * (qy - p0[1]) + (p1[1] - p0[1]) * p0[0]);
                if (A > 0) lo = std::max(lo, -B / A);
                else if (A < 0) hi = std::min(hi, -B / A);
                else if (B < 0) hi = lo - 1;
            }
            if (lo > hi) continue;
            int xa = std::max(x0, int(std::ceil(lo - 0.5))), xb = std::min(x1, int(std::floor(hi - 0.5)));
            if (xa > xb) continue;
            uint64_t m = uint64_t(q[size_t(y + 1) * S + size_t(xb + 1)]) + q[size_t(y) * S + size_t(xa)] -
                         q[size_t(y) * S + size_t(xb + 1)] - q[size_t(y + 1) * S + size_t(xa)];
            out = m > 0;
        }
        if (out) return true;
    }
    return false;
}

namespace {

// The bounding sphere as `compare` frames it: box centre, farthest referenced vertex (radius in
// model units; 0 for a mesh without extent).
void boundingSphere(const TriMesh& mesh, Vec3& centre, double& radius) {
    Box3 box = bounds(mesh);
    centre = (box.min + box.max) * 0.5;
    radius = 0;
    for (const Tri& t : mesh.triangles)
        for (uint32_t v : t) radius = std::max(radius, length(mesh.positions[v] - centre));
}

// The faces that can face an eye: non-degenerate, non-zero area; normal = unnormalized.
struct Faces {
    std::vector<char> usable;
    std::vector<Vec3> normal;
};

Faces usableFaces(const TriMesh& mesh) {
    const uint32_t nf = uint32_t(mesh.triangleCount());
    const auto& P = mesh.positions;
    Faces faces;
    faces.usable.assign(nf, 0);
    faces.normal.assign(nf, Vec3{});
    for (uint32_t f = 0; f < nf; ++f) {
        const Tri& t = mesh.triangles[f];
        if (degenerateIndices(t)) continue;
        faces.normal[f] = cross(P[t[1]] - P[t[0]], P[t[2]] - P[t[0]]);
        faces.usable[f] = length(faces.normal[f]) > 0;
    }
    return faces;
}

// Undirected edges of the usable faces (by edgeKey) and the half-edges (3f + k) carrying them.
struct Edge {
    uint64_t key;
    std::vector<uint32_t> halfEdges;
};

std::vector<Edge> usableEdges(const TriMesh& mesh, const Faces& faces) {
    const EdgeGroups groups = groupEdges(mesh.triangles);
    std::vector<Edge> edges;
    for (size_t g = 0; g < groups.keys.size(); ++g) {
        Edge e{groups.keys[g], {}};
        for (const uint32_t* h = groups.halfEdges.begin(g); h != groups.halfEdges.end(g); ++h)
            if (faces.usable[*h / 3]) e.halfEdges.push_back(*h);
        if (!e.halfEdges.empty()) edges.push_back(std::move(e));
    }
    return edges;
}

// The view's frame (d towards the eye, u and w spanning the image plane) and eye.
OutlineView makeView(Vec3 view, Vec3 centre, double radius, const OutlineOptions& options, int size) {
    OutlineView pr;
    pr.centre = centre;
    pr.d = normalize(view);
    Vec3 a = std::fabs(pr.d.x) < 0.6 ? Vec3{1, 0, 0} : (std::fabs(pr.d.y) < 0.6 ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
    pr.u = normalize(cross(pr.d, a));
    pr.w = cross(pr.d, pr.u);
    pr.perspective = options.viewDistance > 1;
    pr.eye = centre + pr.d * (options.viewDistance * radius);
    pr.size = size;
    return pr;
}

// Raster coordinates of the referenced vertices (ok = in front of the eye), and the mapping that
// fits their projection into the raster with `margin` pixels on each side. False when no
// referenced vertex projects.
struct Projected {
    std::vector<double> x, y;
    std::vector<char> ok;
};

bool projectVertices(const TriMesh& mesh, double margin, OutlineView& pr, Projected& p) {
    const auto& P = mesh.positions;
    p.x.assign(P.size(), 0);
    p.y.assign(P.size(), 0);
    p.ok.assign(P.size(), 0);
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const Tri& t : mesh.triangles)
        for (uint32_t v : t) {
            if (p.ok[v]) continue;
            if (!projectRaw(pr, P[v], p.x[v], p.y[v])) continue;
            p.ok[v] = 1;
            x0 = std::min(x0, p.x[v]), x1 = std::max(x1, p.x[v]);
            y0 = std::min(y0, p.y[v]), y1 = std::max(y1, p.y[v]);
        }
    if (!(x1 >= x0) || !(y1 >= y0)) return false;
    pr.x0 = x0;
    pr.y0 = y0;
    pr.margin = margin;
    const double extent = std::max(x1 - x0, y1 - y0);
    pr.scale = extent > 0 ? (pr.size - 2 * pr.margin) / extent : 1;
    for (size_t v = 0; v < P.size(); ++v) {
        p.x[v] = (p.x[v] - x0) * pr.scale + pr.margin;
        p.y[v] = (p.y[v] - y0) * pr.scale + pr.margin;
    }
    return true;
}

// Coverage: pixel centres inside (or on) a projected face facing the eye (a renderer culls the
// others; on a closed mesh they are covered anyway), plus the vertices' pixels.
void rasterCoverage(const TriMesh& mesh, const std::vector<char>& front, const Projected& p, int G,
                    std::vector<char>& cover) {
    auto at = [&](int x, int y) { return size_t(y) * size_t(G) + size_t(x); };
    std::fill(cover.begin(), cover.end(), 0);
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f) {
        if (!front[f]) continue;
        const Tri& t = mesh.triangles[f];
        if (!p.ok[t[0]] || !p.ok[t[1]] || !p.ok[t[2]]) continue;
        for (uint32_t v : t) cover[at(std::clamp(int(p.x[v]), 0, G - 1), std::clamp(int(p.y[v]), 0, G - 1))] = 1;
        scanTriangle(G, p.x[t[0]], p.y[t[0]], p.x[t[1]], p.y[t[1]], p.x[t[2]], p.y[t[2]], [&](int x, int y) {
            cover[at(x, y)] = 1;
            return false;
        });
    }
}

// pr.outside (pixels uncovered with their 8 neighbours) and its summed-area table.
void markOutside(const std::vector<char>& cover, OutlineView& pr) {
    const int G = pr.size;
    auto at = [&](int x, int y) { return size_t(y) * size_t(G) + size_t(x); };
    pr.outside.assign(size_t(G) * G, 0);
    for (int y = 0; y < G; ++y)
        for (int x = 0; x < G; ++x) {
            bool any = false;
            for (int yy = std::max(0, y - 1); yy <= std::min(G - 1, y + 1) && !any; ++yy)
                for (int xx = std::max(0, x - 1); xx <= std::min(G - 1, x + 1) && !any; ++xx) any = cover[at(xx, yy)];
            pr.outside[at(x, y)] = !any;
        }
    const size_t S = size_t(G) + 1;
    pr.outsideSum.assign(S * S, 0);
    for (int y = 0; y < G; ++y)
        for (int x = 0; x < G; ++x)
            pr.outsideSum[size_t(y + 1) * S + size_t(x + 1)] = pr.outsideSum[size_t(y) * S + size_t(x + 1)] +
                                                               pr.outsideSum[size_t(y + 1) * S + size_t(x)] -
                                                               pr.outsideSum[size_t(y) * S + size_t(x)] +
                                                               uint32_t(pr.outside[at(x, y)]);
}

// Outline pixels (covered with an uncovered 4-neighbour or on the raster's edge), widened by
// `band` pixels.
void markOutlineBand(const std::vector<char>& cover, int G, int band, std::vector<char>& near) {
    auto at = [&](int x, int y) { return size_t(y) * size_t(G) + size_t(x); };
    std::fill(near.begin(), near.end(), 0);
    for (int y = 0; y < G; ++y)
        for (int x = 0; x < G; ++x) {
            if (!cover[at(x, y)]) continue;
            bool border = x == 0 || y == 0 || x == G - 1 || y == G - 1 || !cover[at(x - 1, y)] ||
                          !cover[at(x + 1, y)] || !cover[at(x, y - 1)] || !cover[at(x, y + 1)];
            if (!border) continue;
            for (int yy = std::max(0, y - band); yy <= std::min(G - 1, y + band); ++yy)
                for (int xx = std::max(0, x - band); xx <= std::min(G - 1, x + band); ++xx) near[at(xx, yy)] = 1;
        }
}

// True when edge ab has a sample (every half pixel, both ends included) on a `near` pixel.
bool onOutline(const Projected& p, const std::vector<char>& near, int G, uint32_t a, uint32_t b) {
    if (!p.ok[a] || !p.ok[b]) return false;
    double len = std::hypot(p.x[b] - p.x[a], p.y[b] - p.y[a]);
    int n = 1 + int(std::ceil(2 * len));
    for (int i = 0; i <= n; ++i) {
        double s = double(i) / n;
        int x = std::clamp(int(p.x[a] + s * (p.x[b] - p.x[a])), 0, G - 1);
        int y = std::clamp(int(p.y[a] + s * (p.y[b] - p.y[a])), 0, G - 1);
        if (near[size_t(y) * size_t(G) + size_t(x)]) return true;
    }
    return false;
}

// Contour edges (a facing change across the edge, or a border edge of a usable face) on the
// outline: keeps every face of each, and counts both kinds.
void keepOutlineContours(const std::vector<Edge>& edges, const std::vector<char>& front, const Projected& p,
                         const std::vector<char>& near, int G, OutlineFaces& out) {
    for (const Edge& e : edges) {
        bool anyFront = false, anyBack = false;
        for (uint32_t h : e.halfEdges) (front[h / 3] ? anyFront : anyBack) = true;
        bool contour = (anyFront && anyBack) || e.halfEdges.size() == 1;
        if (!contour) continue;
        ++out.contourEdges;
        uint32_t a = uint32_t(e.key >> 32), b = uint32_t(e.key & 0xffffffffu);
        if (onOutline(p, near, G, a, b)) {
            ++out.outlineEdges;
            for (uint32_t h : e.halfEdges) out.keep[h / 3] = 1;
        }
    }
}

// Extra rings: usable faces sharing a vertex with a kept face, `rings` times.
void addRings(const TriMesh& mesh, const Faces& faces, int rings, std::vector<char>& keep) {
    const uint32_t nf = uint32_t(mesh.triangleCount());
    for (int ring = 0; ring < rings; ++ring) {
        std::vector<char> vmark(mesh.positions.size(), 0);
        for (uint32_t f = 0; f < nf; ++f)
            if (keep[f])
                for (uint32_t v : mesh.triangles[f]) vmark[v] = 1;
        for (uint32_t f = 0; f < nf; ++f)
            if (faces.usable[f])
                for (uint32_t v : mesh.triangles[f]) keep[f] |= vmark[v];
    }
}

}  // namespace

OutlineFaces outlineFaces(const TriMesh& mesh, const std::vector<Vec3>& views, const OutlineOptions& options) {
    const uint32_t nf = uint32_t(mesh.triangleCount());
    const auto& P = mesh.positions;
    OutlineFaces out;
    out.keep.assign(nf, 0);
    if (nf == 0 || views.empty()) return out;
    Vec3 centre;
    double radius = 0;
    boundingSphere(mesh, centre, radius);
    if (!(radius > 0)) return out;
    const Faces faces = usableFaces(mesh);
    const std::vector<Edge> edges = usableEdges(mesh, faces);

    const int G = std::max(64, options.rasterSize);
    const int band = std::max(0, int(std::ceil(options.bandPixels)));
    std::vector<char> cover(size_t(G) * G), near(size_t(G) * G);
    std::vector<char> front(nf);
    Projected projected;
    for (Vec3 view : views) {
        OutlineView pr = makeView(view, centre, radius, options, G);
        for (uint32_t f = 0; f < nf; ++f)
            front[f] = faces.usable[f] && facingEye(pr, faces.normal[f], P[mesh.triangles[f][0]]);
        if (!projectVertices(mesh, band + 2, pr, projected)) continue;
        rasterCoverage(mesh, front, projected, G, cover);
        markOutside(cover, pr);
        markOutlineBand(cover, G, band, near);
        keepOutlineContours(edges, front, projected, near, G, out);
        out.views.push_back(std::move(pr));
    }
    addRings(mesh, faces, options.rings, out.keep);
    for (uint32_t f = 0; f < nf; ++f) out.faces += out.keep[f] != 0;
    return out;
}

}  // namespace lodbake

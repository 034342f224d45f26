// The pictures of an HTML report (html_report.h), made from what compareAssets kept: per view a
// strip of A's render, B's render and their difference, and thumbnails of the texture pages B's
// materials use. Encoded as PNG (texture/codec.h).
#pragma once

#include <cstddef>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/metrics/compare.h"
#include "lodbake/metrics/render.h"

namespace lodbake {

struct ReviewImageOptions {
    int maxViews = 4;                    // views shown, evenly spread over those rendered (all when fewer)
    RenderMode mode = RenderMode::Pbr;   // the render shown (one of kCompareModes)
    double diffGain = 4;                 // |A-B| is multiplied by this, as on the contact sheet
    int thumbnailSide = 256;             // longest side of a page thumbnail, pixels (smaller pages keep their size)
};

// Indices of the views shown out of `views` rendered: min(views, maxViews) of them, evenly spread
// (views on a Fibonacci sphere go from top to bottom, so the first few would all look down).
std::vector<size_t> shownViews(int views, int maxViews);

// Per shown view, a PNG strip [A | B | |A-B| x gain] in options.mode, named "view N".
// \pre result holds renders (CompareOptions::keepRenders); none gives no strips.
std::vector<Image> viewStrips(const CompareResult& result, const ReviewImageOptions& options = {});

// Thumbnails (PNG, RGB or RGBA) of the distinct images the materials of `mesh` reference, each
// named by its use ("baseColor 512x256"). An image that cannot be decoded (KTX2) is left out.
std::vector<Image> pageThumbnails(const Asset& asset, const TriMesh& mesh, const ReviewImageOptions& options = {});

}  // namespace lodbake

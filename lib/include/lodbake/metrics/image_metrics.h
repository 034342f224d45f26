// Image-space comparison of two renderings of the same view (see render.h).
#pragma once

#include <cstddef>
#include <vector>

#include "lodbake/metrics/render.h"

namespace lodbake {

// PSNR is computed over the pixels covered by either silhouette (the union mask), on the sRGB
// values in [0,1] (peak 1), all three channels. When the images are identical over the mask
// (or the mask is empty) the PSNR is capped at kMaxPsnr.
constexpr double kMaxPsnr = 100.0;

// Sums that can be pooled over several views (so the pooled PSNR is not a mean of logs).
struct ImageMetrics {
    double psnr = kMaxPsnr;  // dB, pooled over views: 10 log10(1 / pooled MSE), capped
    double worstPsnr = kMaxPsnr;  // lowest single-view PSNR
    double ssim = 1;         // mean SSIM on luminance, 8x8 windows (stride 4) touching the union mask
    double worstSsim = 1;    // lowest single-view SSIM
    double iou = 1;          // silhouette intersection over union, pooled over views (1 if both empty)
    double worstIou = 1;
    // PSNR over the seam band: the union pixels that b (the candidate) marks as near a visible
    // texture seam (Rendering::seam), pooled over views; kMaxPsnr when no view shows a seam.
    double seamPsnr = kMaxPsnr;
    size_t seamPixels = 0;
    double seamSquaredErrorSum = 0;

    // Pooling state (sums over views).
    double squaredErrorSum = 0;  // over union pixels x 3 channels
    size_t unionPixels = 0, intersectionPixels = 0;
    double ssimSum = 0;
    size_t ssimWindows = 0;
    size_t views = 0;
};

// Metrics of one view.
ImageMetrics compareImages(const Rendering& a, const Rendering& b);

// Adds the view metrics `v` into the pooled `total` and recomputes its figures.
void accumulate(ImageMetrics& total, const ImageMetrics& v);

}  // namespace lodbake

// PSNR over the union of silhouettes, SSIM on luminance (Wang et al. 2004, "Image quality
// assessment: from error visibility to structural similarity") with 8x8 windows at stride 4,
// and silhouette IoU. See image_metrics.h for the conventions.
#include "lodbake/metrics/image_metrics.h"

#include <algorithm>
#include <cmath>

namespace lodbake {
namespace {

constexpr int kWindow = 8, kStride = 4;
constexpr double kC1 = 0.01 * 0.01, kC2 = 0.03 * 0.03;

double psnrOf(double squaredErrorSum, size_t values) {
    if (values == 0 || squaredErrorSum <= 0) return kMaxPsnr;
    double mse = squaredErrorSum / static_cast<double>(values);
    return std::min(kMaxPsnr, 10 * std::log10(1.0 / mse));
}

void finish(ImageMetrics& m) {
    m.psnr = psnrOf(m.squaredErrorSum, m.unionPixels * 3);
    m.iou = m.unionPixels == 0 ? 1.0 : static_cast<double>(m.intersectionPixels) / m.unionPixels;
    m.ssim = m.ssimWindows == 0 ? 1.0 : m.ssimSum / static_cast<double>(m.ssimWindows);
    m.seamPsnr = psnrOf(m.seamSquaredErrorSum, m.seamPixels * 3);
}

}  // namespace

ImageMetrics compareImages(const Rendering& a, const Rendering& b) {
    ImageMetrics m;
    m.views = 1;
    if (a.width != b.width || a.height != b.height) return m;
    const int W = a.width, H = a.height;
    const size_t n = static_cast<size_t>(W) * H;
    std::vector<double> ya(n), yb(n);
    std::vector<uint8_t> mask(n);
    for (size_t i = 0; i < n; ++i) {
        bool ca = a.coverage[i] != 0, cb = b.coverage[i] != 0;
        mask[i] = ca || cb;
        if (mask[i]) {
            ++m.unionPixels;
            if (ca && cb) ++m.intersectionPixels;
            const bool seam = i < b.seam.size() && b.seam[i] != 0;
            m.seamPixels += seam;
            for (int c = 0; c < 3; ++c) {
                double d = static_cast<double>(a.rgb[i * 3 + c]) - b.rgb[i * 3 + c];
                m.squaredErrorSum += d * d;
                if (seam) m.seamSquaredErrorSum += d * d;
            }
        }
        ya[i] = 0.2126 * a.rgb[i * 3] + 0.7152 * a.rgb[i * 3 + 1] + 0.0722 * a.rgb[i * 3 + 2];
        yb[i] = 0.2126 * b.rgb[i * 3] + 0.7152 * b.rgb[i * 3 + 1] + 0.0722 * b.rgb[i * 3 + 2];
    }
    for (int y0 = 0; y0 + kWindow <= H; y0 += kStride)
        for (int x0 = 0; x0 + kWindow <= W; x0 += kStride) {
            bool touches = false;
            double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
            for (int y = y0; y < y0 + kWindow; ++y)
                for (int x = x0; x < x0 + kWindow; ++x) {
                    size_t i = static_cast<size_t>(y) * W + x;
                    touches = touches || mask[i];
                    sa += ya[i];
                    sb += yb[i];
                    saa += ya[i] * ya[i];
                    sbb += yb[i] * yb[i];
                    sab += ya[i] * yb[i];
                }
            if (!touches) continue;
            const double k = kWindow * kWindow;
            double ma = sa / k, mb = sb / k;
            double va = std::max(0.0, saa / k - ma * ma), vb = std::max(0.0, sbb / k - mb * mb);
            double cov = sab / k - ma * mb;
            double s = ((2 * ma * mb + kC1) * (2 * cov + kC2)) / ((ma * ma + mb * mb + kC1) * (va + vb + kC2));
            m.ssimSum += s;
            ++m.ssimWindows;
        }
    finish(m);
    m.worstPsnr = m.psnr;
    m.worstSsim = m.ssim;
    m.worstIou = m.iou;
    return m;
}

void accumulate(ImageMetrics& total, const ImageMetrics& v) {
    bool first = total.views == 0;
    total.squaredErrorSum += v.squaredErrorSum;
    total.unionPixels += v.unionPixels;
    total.intersectionPixels += v.intersectionPixels;
    total.ssimSum += v.ssimSum;
    total.ssimWindows += v.ssimWindows;
    total.seamSquaredErrorSum += v.seamSquaredErrorSum;
    total.seamPixels += v.seamPixels;
    total.views += v.views;
    total.worstPsnr = first ? v.worstPsnr : std::min(total.worstPsnr, v.worstPsnr);
    total.worstSsim = first ? v.worstSsim : std::min(total.worstSsim, v.worstSsim);
    total.worstIou = first ? v.worstIou : std::min(total.worstIou, v.worstIou);
    finish(total);
}

}  // namespace lodbake

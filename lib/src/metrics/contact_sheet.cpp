// writeContactSheet (compare.h): the renders kept by compareAssets tiled into one PNG
// (texture/codec.h), written to a temporary file beside the target and renamed into place.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "lodbake/core/errors.h"
#include "lodbake/metrics/compare.h"
#include "lodbake/texture/codec.h"

namespace lodbake {

void writeContactSheet(const std::string& path, const CompareResult& result, const ContactSheetOptions& options) {
    if (result.rendersA.empty() || result.rendersA.size() != result.rendersB.size())
        throw InvalidInput(path + ": no renders to put on a contact sheet");
    const int tw = result.rendersA[0][0].width, th = result.rendersA[0][0].height;
    const int modes = static_cast<int>(result.rendersA[0].size());
    const int cols = 3 * modes, rows = static_cast<int>(result.rendersA.size());
    const int W = tw * cols, H = th * rows;
    std::vector<uint8_t> pixels(static_cast<size_t>(W) * H * 3, 0);
    auto put = [&](int col, int row, const std::vector<float>& rgb) {
        for (int y = 0; y < th; ++y)
            for (int x = 0; x < tw; ++x)
                for (int c = 0; c < 3; ++c) {
                    float v = rgb[(static_cast<size_t>(y) * tw + x) * 3 + c];
                    v = std::fmin(std::fmax(v, 0.f), 1.f);
                    pixels[((static_cast<size_t>(row) * th + y) * W + col * tw + x) * 3 + c] =
                        static_cast<uint8_t>(std::lround(v * 255));
                }
    };
    for (int row = 0; row < rows; ++row)
        for (int mode = 0; mode < modes; ++mode) {
            const Rendering& a = result.rendersA[row][mode];
            const Rendering& b = result.rendersB[row][mode];
            if (a.width != tw || b.width != tw || a.height != th || b.height != th)
                throw InvalidInput(path + ": renders of different sizes");
            std::vector<float> diff(a.rgb.size());
            for (size_t i = 0; i < diff.size(); ++i)
                diff[i] = static_cast<float>(std::fabs(a.rgb[i] - b.rgb[i]) * options.diffGain);
            put(mode * 3, row, a.rgb);
            put(mode * 3 + 1, row, b.rgb);
            put(mode * 3 + 2, row, diff);
        }
    std::filesystem::path target(path);
    std::string tmp = (target.parent_path() / ("." + target.filename().string() + ".tmp.png")).string();
    const Image png = encodePng(pixels, W, H);
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(png.encoded.data()), std::streamsize(png.encoded.size()));
    f.close();
    if (!f) {
        std::string e = std::strerror(errno);
        std::remove(tmp.c_str());
        throw IOError(path + ": cannot write contact sheet: " + e);
    }
    std::error_code ec;
    std::filesystem::rename(tmp, target, ec);
    if (ec) {
        std::remove(tmp.c_str());
        throw IOError(path + ": cannot write contact sheet: " + ec.message());
    }
}

}  // namespace lodbake

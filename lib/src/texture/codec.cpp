// Image decoding, encoding and checking with OpenImageIO (see codec.h). Encoded bytes are read
// from and written to memory through OpenImageIO's IO proxies.
#include "lodbake/texture/codec.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <mutex>

#include <fcntl.h>
#include <unistd.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include "lodbake/core/errors.h"

namespace lodbake {
namespace {

// OpenImageIO 2.4's JPEG reader is not thread-safe on open: it parses an embedded ICC profile
// through state all threads share. Opens therefore never overlap: each takes this lock. Pixel
// reads need none, so decodes still run side by side.
std::mutex& openMutex() {
    static std::mutex m;
    return m;
}

// libpng and libjpeg print their own messages on stderr before OpenImageIO reports the failure,
// which would break the one-line error: stderr goes to /dev/null while an image is decoded (at
// load time, before any worker thread or progress line exists).
class QuietStderr {
public:
    QuietStderr() {
        std::fflush(stderr);
        saved_ = dup(STDERR_FILENO);
        int null = open("/dev/null", O_WRONLY);
        if (saved_ >= 0 && null >= 0) dup2(null, STDERR_FILENO);
        if (null >= 0) close(null);
    }
    ~QuietStderr() {
        std::fflush(stderr);
        if (saved_ >= 0) {
            dup2(saved_, STDERR_FILENO);
            close(saved_);
        }
    }
    QuietStderr(const QuietStderr&) = delete;
    QuietStderr& operator=(const QuietStderr&) = delete;

private:
    int saved_ = -1;
};

// Why a PNG stream is incomplete (a chunk that runs past the data, or no IEND chunk), or "" when
// its chunks are whole or it is not a PNG. Such a stream is rejected before decoding: libpng
// unwinds from OpenImageIO's short-read callback with longjmp, which skips the destructor of that
// callback's error string (a leak in libOpenImageIO on every cut PNG).
std::string pngTruncation(const std::vector<unsigned char>& b) {
    static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (b.size() < 8 || std::memcmp(b.data(), kSignature, 8) != 0) return "";
    for (size_t off = 8;;) {
        // Chunk: 4-byte big-endian data length, 4-byte type, data, 4-byte CRC.
        if (b.size() - off < 12) return "truncated PNG: no IEND chunk";
        size_t length = size_t(b[off]) << 24 | size_t(b[off + 1]) << 16 | size_t(b[off + 2]) << 8 | size_t(b[off + 3]);
        if (length > b.size() - off - 12)
            return "truncated PNG: chunk at byte " + std::to_string(off) + " runs past the end";
        if (std::memcmp(&b[off + 4], "IEND", 4) == 0) return "";
        off += 12 + length;
    }
}

// Size and channels of a baseline or progressive JPEG from its frame header (the first SOFn
// segment), as OpenImageIO's reader reports them: one channel for grey, three for colour; false
// for anything else (four components, a height defined later by a DNL segment, no frame header
// before the scan), which goes through OpenImageIO. OpenImageIO's open() decodes every scan of a
// progressive JPEG, so the header check reads the size here.
bool jpegFrameHeader(const std::vector<unsigned char>& b, int& width, int& height, int& channels) {
    if (b.size() < 4 || b[0] != 0xFF || b[1] != 0xD8) return false;
    for (size_t off = 2; off + 4 <= b.size();) {
        if (b[off] != 0xFF) return false;
        const unsigned char marker = b[off + 1];
        if (marker == 0xFF) { ++off; continue; }  // fill byte
        if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) { off += 2; continue; }  // no length
        if (marker == 0xD9 || marker == 0xDA) return false;  // end of image, or a scan before the frame
        const size_t length = size_t(b[off + 2]) << 8 | b[off + 3];
        if (length < 2 || off + 2 + length > b.size()) return false;
        const bool frame = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
        if (frame) {
            if (length < 8) return false;
            const unsigned char* f = &b[off + 4];  // precision, height, width, components
            height = int(f[1]) << 8 | f[2];
            width = int(f[3]) << 8 | f[4];
            channels = f[5];
            return width > 0 && height > 0 && (channels == 1 || channels == 3);
        }
        off += 2 + length;
    }
    return false;
}

void checkImage(const std::string& path, Image& img, size_t index, ImageCheck check) {
    auto fail = [&](const std::string& problem) {
        throw InvalidInput(path + ": image " + std::to_string(index) + (img.name.empty() ? "" : " '" + img.name + "'") +
                           ": " + problem);
    };
    if (img.encoded.empty()) fail("no image data");
    const std::string kind = img.mimeType.empty() ? "image" : img.mimeType;
    if (check == ImageCheck::Decode) {
        std::string cut = pngTruncation(img.encoded);
        if (!cut.empty()) fail("cannot decode " + kind + ": " + cut);
    }
    if (check == ImageCheck::Header && img.mimeType == "image/jpeg" && jpegFrameHeader(img.encoded, img.width, img.height, img.channels))
        return;
    std::string name = img.mimeType == "image/jpeg" ? "image.jpg" : "image.png";
    QuietStderr quiet;
    OIIO::Filesystem::IOMemReader reader(img.encoded.data(), img.encoded.size());
    OIIO::Filesystem::IOProxy* proxy = &reader;
    OIIO::ImageSpec config;
    config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    OIIO::ImageInput::unique_ptr in;
    std::string openError;
    {
        const std::lock_guard<std::mutex> lock(openMutex());
        in = OIIO::ImageInput::create(name, false, &config, proxy);
        OIIO::ImageSpec opened;
        if (in && !in->open(name, opened, config)) in.reset();
        if (!in) openError = firstLine(OIIO::geterror());
    }
    if (!in) fail("cannot decode " + kind + (openError.empty() ? "" : ": " + openError));
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) fail("invalid image size");
    if (check == ImageCheck::Decode) {
        std::vector<unsigned char> pixels(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
        if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels.data()))
            fail("cannot decode " + kind + ": " + firstLine(in->geterror()));
    }
    img.width = spec.width;
    img.height = spec.height;
    img.channels = spec.nchannels;
    in->close();
}

// PNG encoding: zlib level 4 with every row's filter fixed to Average. libpng's default (level 6,
// the best of five filters tried per row) takes about four times as long on baked pages for files
// only 3-8% smaller; the pixels are the same and the bytes are still a function of them alone.
constexpr int kPngDeflateLevel = 4;
constexpr int kPngFilterAverage = 0x40;  // libpng's PNG_FILTER_AVG

// Encodes 8-bit pixels (`channels` interleaved) as PNG or JPEG in memory; `tagSrgb` records the
// sRGB colour space in the file (PNG: an sRGB chunk).
std::vector<unsigned char> encode8(const unsigned char* px, int width, int height, int channels, ImageFormat format,
                                   int jpegQuality, bool tagSrgb) {
    bool jpeg = format == ImageFormat::Jpeg;
    std::string fname = jpeg ? "atlas.jpg" : "atlas.png";
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput vec(bytes);
    OIIO::Filesystem::IOProxy* proxy = &vec;
    auto out = OIIO::ImageOutput::create(fname, proxy);
    if (!out) throw IOError("encodeImage: no " + std::string(jpeg ? "JPEG" : "PNG") + " encoder: " + OIIO::geterror());
    OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
    if (channels == 4) {
        spec.alpha_channel = 3;
        spec.attribute("oiio:UnassociatedAlpha", 1);  // straight alpha, as given: OIIO would divide colour by it
    }
    if (tagSrgb) spec.attribute("oiio:ColorSpace", "sRGB");
    if (jpeg) spec.attribute("Compression", "jpeg:" + std::to_string(std::clamp(jpegQuality, 1, 100)));
    if (!jpeg) {
        spec.attribute("png:compressionLevel", kPngDeflateLevel);
        spec.attribute("png:filter", kPngFilterAverage);
    }
    spec.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
    if (!out->open(fname, spec) || !out->write_image(OIIO::TypeDesc::UINT8, px) || !out->close())
        throw IOError("encodeImage: cannot encode: " + out->geterror());
    return bytes;
}

void checkSize(const char* what, size_t values, int width, int height, int channels = 3) {
    if (channels < 1 || channels > 4) throw InvalidInput(std::string(what) + ": " + std::to_string(channels) + " channels");
    if (width <= 0 || height <= 0 || values != size_t(width) * size_t(height) * size_t(channels))
        throw InvalidInput(std::string(what) + ": pixel array does not match " + std::to_string(width) + "x" + std::to_string(height));
}

Image encodedImage(std::vector<unsigned char> bytes, ImageFormat format, int width, int height, int channels,
                   const std::string& name) {
    Image img;
    img.name = name;
    img.mimeType = format == ImageFormat::Jpeg ? "image/jpeg" : "image/png";
    img.encoded.assign(bytes.begin(), bytes.end());
    img.width = width;
    img.height = height;
    img.channels = channels;
    return img;
}

}  // namespace

bool decodeImage(const Image& image, DecodedImage& out, std::string& error, DecodeDepth depth) {
    if (image.encoded.empty()) {
        error = "image '" + image.name + "' has no data";
        return false;
    }
    std::string cut = pngTruncation(image.encoded);
    if (!cut.empty()) {
        error = "image '" + image.name + "' cannot be decoded: " + cut;
        return false;
    }
    std::string name = image.mimeType == "image/jpeg" ? "image.jpg" : "image.png";
    OIIO::Filesystem::IOMemReader reader(const_cast<uint8_t*>(image.encoded.data()), image.encoded.size());
    OIIO::ImageInput::unique_ptr in;
    {
        const std::lock_guard<std::mutex> lock(openMutex());
        // create + set_ioproxy: OIIO 2.4.7's ImageInput::open(name, config, proxy) fails on memory proxies.
        in = OIIO::ImageInput::create(image.mimeType == "image/jpeg" ? "jpeg" : "png");
        OIIO::ImageSpec opened, config;
        // glTF images carry straight alpha: OIIO would premultiply colour by it.
        config.attribute("oiio:UnassociatedAlpha", 1);
        if (!in || !in->set_ioproxy(&reader) || !in->open(name, opened, config)) {
            error = "image '" + image.name + "' cannot be decoded: " + OIIO::geterror();
            return false;
        }
    }
    const OIIO::ImageSpec& spec = in->spec();
    int w = spec.width, h = spec.height, nc = spec.nchannels;
    if (w <= 0 || h <= 0 || nc <= 0) {
        error = "image '" + image.name + "' is empty";
        return false;
    }
    const size_t values = static_cast<size_t>(w) * h * nc;
    const bool eightBit = depth == DecodeDepth::KeepEightBit && spec.format == OIIO::TypeDesc::UINT8;
    out.pixels.clear();
    out.bytes.clear();
    if (eightBit)
        out.bytes.assign(values, 0);
    else
        out.pixels.assign(values, 0.f);
    if (!in->read_image(0, 0, 0, nc, eightBit ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT,
                        eightBit ? static_cast<void*>(out.bytes.data()) : static_cast<void*>(out.pixels.data()))) {
        error = "image '" + image.name + "' cannot be decoded: " + in->geterror();
        return false;
    }
    in->close();
    out.width = w;
    out.height = h;
    out.channels = nc;
    return true;
}

std::pair<int, int> imageSize(const Image& image) {
    if (image.width > 0 && image.height > 0) return {image.width, image.height};
    if (image.encoded.empty()) return {0, 0};
    OIIO::Filesystem::IOMemReader reader(const_cast<uint8_t*>(image.encoded.data()), image.encoded.size());
    const std::lock_guard<std::mutex> lock(openMutex());
    auto in = OIIO::ImageInput::create(image.mimeType == "image/jpeg" ? "jpeg" : "png");
    OIIO::ImageSpec opened;
    if (!in || !in->set_ioproxy(&reader) || !in->open(image.mimeType == "image/jpeg" ? "image.jpg" : "image.png", opened)) {
        OIIO::geterror();  // clears the message
        return {0, 0};
    }
    const std::pair<int, int> size{in->spec().width, in->spec().height};
    in->close();
    return size;
}

void checkImages(Asset& asset, ImageCheck check) {
    for (size_t i = 0; i < asset.images.size(); ++i) checkImage(asset.sourcePath, asset.images[i], i, check);
}

Image encodeImage(const std::vector<float>& rgb, int width, int height, ImageFormat format, int jpegQuality,
                  const std::string& name) {
    EncodeOptions o;
    o.format = format;
    o.jpegQuality = jpegQuality;
    return encodeImage(rgb, width, height, o, name);
}

Image encodeImage(const std::vector<float>& values, int width, int height, const EncodeOptions& o, const std::string& name) {
    checkSize("encodeImage", values.size(), width, height, o.channels);
    if (o.channels == 4 && o.format == ImageFormat::Jpeg) throw InvalidInput("encodeImage: JPEG has no alpha channel");
    // Each value rounded to the nearest step, halves up (lround of v x 255 in float, taken as
    // floor(+0.5) in double, where the sum is exact for the float products 0..255).
    std::vector<unsigned char> px(values.size());
    for (size_t i = 0; i < values.size(); ++i) {
        float v = std::isfinite(values[i]) ? std::clamp(values[i], 0.f, 1.f) : 0.f;
        px[i] = static_cast<unsigned char>(int(double(v * 255.f) + 0.5));
    }
    return encodedImage(encode8(px.data(), width, height, o.channels, o.format, o.jpegQuality, o.srgb), o.format, width, height,
                        o.channels, name);
}

Image encodePng(const std::vector<uint8_t>& pixels, int width, int height, const std::string& name, int channels) {
    checkSize("encodePng", pixels.size(), width, height, channels);
    return encodedImage(encode8(pixels.data(), width, height, channels, ImageFormat::Png, 90, false), ImageFormat::Png, width,
                        height, channels, name);
}

}  // namespace lodbake

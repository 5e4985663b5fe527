// OpenImageIO output of surfaces (PNG for RGBA8, EXR for float/depth, TIFF for UINT data),
// written to "<path>.partial<ext>" and renamed on success.
#include "image_out.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include <OpenImageIO/imageio.h>

namespace tessera::cli {
namespace {

void writeImage(const std::string& path, int width, int height, int channels, OIIO::TypeDesc type, const void* pixels,
                const std::vector<std::string>& channelNames) {
    const std::filesystem::path target(path);
    const std::filesystem::path tmp = target.parent_path() / (target.stem().string() + ".partial" + target.extension().string());
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out) throw std::runtime_error(path + ": no image writer for this extension (" + OIIO::geterror() + ")");
    OIIO::ImageSpec spec(width, height, channels, type);
    spec.channelnames = channelNames;
    bool ok = out->open(tmp.string(), spec) && out->write_image(type, pixels);
    ok = out->close() && ok;
    if (!ok) {
        const std::string err = out->geterror();
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error(path + ": " + err);
    }
    std::error_code ec;
    std::filesystem::rename(tmp, target, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error(path + ": cannot rename into place: " + ec.message());
    }
}

} // namespace

void writeSurface(const Surface& s, const std::string& path) {
    const int w = int(s.width()), h = int(s.height());
    const FormatInfo& info = formatInfo(s.format());
    if (s.format() == Format::R8G8B8A8_UNORM || s.format() == Format::R8G8B8A8_UNORM_SRGB) {
        std::vector<std::uint8_t> px(std::size_t(w) * h * 4);
        for (std::uint32_t y = 0; y < s.height(); ++y)
            for (std::uint32_t x = 0; x < s.width(); ++x)
                for (int c = 0; c < 4; ++c) px[(std::size_t(y) * w + x) * 4 + c] = std::to_integer<std::uint8_t>(s.texel(x, y)[c]);
        writeImage(path, w, h, 4, OIIO::TypeDesc::UINT8, px.data(), {"R", "G", "B", "A"});
    } else if (info.kind == FormatKind::Uint) {
        const int ch = int(info.channels);
        std::vector<std::uint32_t> px(std::size_t(w) * h * ch);
        for (std::uint32_t y = 0; y < s.height(); ++y)
            for (std::uint32_t x = 0; x < s.width(); ++x) {
                const glm::uvec4 v = s.loadUint(x, y);
                for (int c = 0; c < ch; ++c) px[(std::size_t(y) * w + x) * ch + c] = v[c];
            }
        writeImage(path, w, h, ch, OIIO::TypeDesc::UINT32, px.data(), ch == 1 ? std::vector<std::string>{"R"} : std::vector<std::string>{"R", "G"});
    } else if (info.hasDepth) {
        std::vector<float> px(std::size_t(w) * h);
        for (std::uint32_t y = 0; y < s.height(); ++y)
            for (std::uint32_t x = 0; x < s.width(); ++x) px[std::size_t(y) * w + x] = s.loadDepth(x, y);
        writeImage(path, w, h, 1, OIIO::TypeDesc::FLOAT, px.data(), {"Z"});
    } else {
        std::vector<float> px(std::size_t(w) * h * 4);
        for (std::uint32_t y = 0; y < s.height(); ++y)
            for (std::uint32_t x = 0; x < s.width(); ++x) {
                const glm::vec4 v = s.load(x, y);
                for (int c = 0; c < 4; ++c) px[(std::size_t(y) * w + x) * 4 + c] = v[c];
            }
        writeImage(path, w, h, 4, OIIO::TypeDesc::FLOAT, px.data(), {"R", "G", "B", "A"});
    }
}

void writeStencil(const Surface& s, const std::string& path) {
    std::vector<std::uint8_t> px(std::size_t(s.width()) * s.height());
    for (std::uint32_t y = 0; y < s.height(); ++y)
        for (std::uint32_t x = 0; x < s.width(); ++x) px[std::size_t(y) * s.width() + x] = s.loadStencil(x, y);
    writeImage(path, int(s.width()), int(s.height()), 1, OIIO::TypeDesc::UINT8, px.data(), {"S"});
}

} // namespace tessera::cli

// OpenImageIO output of surfaces: PNG/TIFF bytes for 8-bit UNORM, EXR (half or float) for
// shader-visible values, TIFF uint32 for UINT data; each encoded in memory without timestamps
// and written by writeFileAtomically (unique temporary, every write checked, then renamed).
#include <tessera/io/image_writer.h>

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <ctime>
#include <stdexcept>
#include <string>
#include <vector>

#ifndef TESSERA_NO_OIIO
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#endif

#include <tessera/io/atomic_file.h>

namespace tessera {
namespace {

std::string lowerExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

// Pixel types of the files written and of the memory they are written from.
enum class PixelType { UInt8, UInt32, Half, Float };

#ifndef TESSERA_NO_OIIO
OIIO::TypeDesc typeDesc(PixelType t) {
    switch (t) {
    case PixelType::UInt8: return OIIO::TypeDesc::UINT8;
    case PixelType::UInt32: return OIIO::TypeDesc::UINT32;
    case PixelType::Half: return OIIO::TypeDesc::HALF;
    case PixelType::Float: break;
    }
    return OIIO::TypeDesc::FLOAT;
}

// The DateTime attribute every file gets: OIIO's EXR and TIFF writers would otherwise stamp the
// current time (EXR capDate, TIFF DateTime), so that one command wrote different bytes each run.
// SOURCE_DATE_EPOCH (seconds since 1970-01-01 UTC, as in the Reproducible Builds specification)
// gives a fixed UTC time; without it the value is empty (TIFF and PNG then carry no date, EXR an
// empty capDate).
std::string fileDateTime() {
    const char* env = std::getenv("SOURCE_DATE_EPOCH");
    if (!env || !*env) return {};
    char* end = nullptr;
    errno = 0;
    const long long seconds = std::strtoll(env, &end, 10);
    if (errno != 0 || *end != '\0' || seconds < 0) return {};  // malformed: no date rather than a wrong one
    const std::time_t t = static_cast<std::time_t>(seconds);
    std::tm utc{};
    if (!gmtime_r(&t, &utc)) return {};
    char text[32];
    if (std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", &utc) == 0) return {};  // TIFF/EXIF form
    return text;
}

// Encodes the image into memory through OIIO's I/O proxy, then writes the bytes with
// writeFileAtomically, which checks every system call: OIIO's own file writes do not report a
// full disk. Returns FNV-1a 64 of the bytes written.
std::uint64_t writeImage(const std::filesystem::path& target, int width, int height, int channels, PixelType fileTypeIn,
                         PixelType memTypeIn, const void* pixels, const std::vector<std::string>& channelNames) {
    const OIIO::TypeDesc fileType = typeDesc(fileTypeIn), memType = typeDesc(memTypeIn);
    auto out = OIIO::ImageOutput::create(target.string());
    if (!out) throw std::runtime_error(target.string() + ": no image writer for this extension (" + OIIO::geterror() + ")");
    if (!out->supports("ioproxy"))  // png, openexr and tiff do (OIIO 2.4); never write around the checks
        throw std::runtime_error(target.string() + ": the " + std::string(out->format_name()) +
                                 " writer cannot encode into memory, so a failed write could go unnoticed");
    OIIO::ImageSpec spec(width, height, channels, fileType);
    spec.channelnames = channelNames;
    // Pixels are written as stored: OIIO would otherwise treat RGBA as premultiplied and divide
    // by alpha on the way into PNG (PNG holds unassociated alpha).
    spec.attribute("oiio:UnassociatedAlpha", 1);
    spec.attribute("DateTime", fileDateTime());
    spec.alpha_channel = -1;
    for (int c = 0; c < channels; ++c)
        if (channelNames[std::size_t(c)] == "A") spec.alpha_channel = c;
    std::vector<unsigned char> encoded;
    OIIO::Filesystem::IOVecOutput proxy(encoded);
    bool ok = out->set_ioproxy(&proxy) && out->open(target.string(), spec) && out->write_image(memType, pixels);
    ok = out->close() && ok;
    if (!ok || encoded.empty()) {
        const std::string err = out->geterror();
        throw std::runtime_error(target.string() + ": cannot encode the image: " + (err.empty() ? std::string("no bytes produced") : err));
    }
    writeFileAtomically(target, encoded);
    return fnv1a64(encoded);
}
#else
// Built with TESSERA_WITH_OIIO=OFF (benchmark binaries for hosts without OpenImageIO).
std::uint64_t writeImage(const std::filesystem::path& target, int, int, int, PixelType, PixelType, const void*,
                         const std::vector<std::string>&) {
    throw std::runtime_error(target.string() + ": this tessera was built without OpenImageIO (TESSERA_WITH_OIIO=OFF) and writes no images");
}
#endif

const std::vector<std::string>& colorChannelNames(std::uint32_t count) {
    static const std::vector<std::string> names[4] = {{"R"}, {"R", "G"}, {"R", "G", "B"}, {"R", "G", "B", "A"}};
    return names[count - 1];
}

void checkSample(const Surface& s, std::uint32_t sample, const std::filesystem::path& path) {
    if (sample >= s.sampleCount())
        throw std::runtime_error(path.string() + ": sample " + std::to_string(sample) + " of a " +
                                 std::to_string(s.sampleCount()) + "-sample surface");
}

} // namespace

std::string losslessExtension(Format format) {
    const FormatInfo& info = formatInfo(format);
    if (format == Format::R8G8B8A8_UNORM || format == Format::R8G8B8A8_UNORM_SRGB) return ".png";
    if (info.kind == FormatKind::Uint) return ".tif";
    return ".exr";
}

std::uint64_t writeSurface(const Surface& s, const std::filesystem::path& path, ExrPixelType exrType, std::uint32_t sample) {
    checkSample(s, sample, path);
    const int w = int(s.width()), h = int(s.height());
    const FormatInfo& info = formatInfo(s.format());
    const std::string ext = lowerExtension(path);
    const bool rgba8 = s.format() == Format::R8G8B8A8_UNORM || s.format() == Format::R8G8B8A8_UNORM_SRGB;
    if (ext == ".exr") {
        const std::uint32_t ch = info.hasDepth ? 1 : info.channels;
        std::vector<float> px(std::size_t(w) * h * ch);
        for (std::uint32_t y = 0; y < s.height(); ++y)
            for (std::uint32_t x = 0; x < s.width(); ++x) {
                float* dst = &px[(std::size_t(y) * w + x) * ch];
                if (info.hasDepth) {
                    dst[0] = s.loadDepth(x, y, sample);
                } else if (info.kind == FormatKind::Uint) {
                    throw std::runtime_error(path.string() + ": " + std::string(info.name) +
                                             " holds integers; write it as .tif (uint32 channels)");
                } else {
                    const glm::vec4 v = s.load(x, y, sample);
                    for (std::uint32_t c = 0; c < ch; ++c) dst[c] = v[int(c)];
                }
            }
        const PixelType fileType = exrType == ExrPixelType::Half ? PixelType::Half : PixelType::Float;
        return writeImage(path, w, h, int(ch), fileType, PixelType::Float, px.data(),
                   info.hasDepth ? std::vector<std::string>{"Z"} : colorChannelNames(ch));
    } else if (rgba8 && (ext == ".png" || ext == ".tif" || ext == ".tiff")) {
        std::vector<std::uint8_t> px(std::size_t(w) * h * 4);
        for (std::uint32_t y = 0; y < s.height(); ++y)
            for (std::uint32_t x = 0; x < s.width(); ++x)
                for (int c = 0; c < 4; ++c)
                    px[(std::size_t(y) * w + x) * 4 + std::size_t(c)] = std::to_integer<std::uint8_t>(s.texel(x, y, sample)[c]);
        return writeImage(path, w, h, 4, PixelType::UInt8, PixelType::UInt8, px.data(), colorChannelNames(4));
    } else if (info.kind == FormatKind::Uint && (ext == ".tif" || ext == ".tiff")) {
        const std::uint32_t ch = info.channels;
        std::vector<std::uint32_t> px(std::size_t(w) * h * ch);
        for (std::uint32_t y = 0; y < s.height(); ++y)
            for (std::uint32_t x = 0; x < s.width(); ++x) {
                const glm::uvec4 v = s.loadUint(x, y, sample);
                for (std::uint32_t c = 0; c < ch; ++c) px[(std::size_t(y) * w + x) * ch + c] = v[int(c)];
            }
        return writeImage(path, w, h, int(ch), PixelType::UInt32, PixelType::UInt32, px.data(), colorChannelNames(ch));
    } else {
        throw std::runtime_error(path.string() + ": cannot store " + std::string(info.name) + " as '" + ext +
                                 "' without loss (use " + losslessExtension(s.format()) + ")");
    }
}

Surface withOpaqueAlpha(const Surface& s) {
    Surface out = s;
    const FormatInfo& info = formatInfo(s.format());
    if (info.channels != 4 || info.hasDepth || info.kind == FormatKind::Uint) return out;
    for (std::uint32_t y = 0; y < s.height(); ++y)
        for (std::uint32_t x = 0; x < s.width(); ++x)
            for (std::uint32_t i = 0; i < s.sampleCount(); ++i) {
                if (s.format() == Format::R8G8B8A8_UNORM || s.format() == Format::R8G8B8A8_UNORM_SRGB) {
                    out.texel(x, y, i)[3] = std::byte{255};
                } else {
                    glm::vec4 v = s.load(x, y, i);
                    v.w = 1.0f;
                    out.store(x, y, i, v);
                }
            }
    return out;
}

std::uint64_t writeStencil(const Surface& s, const std::filesystem::path& path, std::uint32_t sample) {
    checkSample(s, sample, path);
    if (!formatInfo(s.format()).hasStencil)
        throw std::runtime_error(path.string() + ": " + std::string(formatInfo(s.format()).name) + " has no stencil");
    std::vector<std::uint8_t> px(std::size_t(s.width()) * s.height());
    for (std::uint32_t y = 0; y < s.height(); ++y)
        for (std::uint32_t x = 0; x < s.width(); ++x) px[std::size_t(y) * s.width() + x] = s.loadStencil(x, y, sample);
    return writeImage(path, int(s.width()), int(s.height()), 1, PixelType::UInt8, PixelType::UInt8, px.data(), {"S"});
}

} // namespace tessera

// `tessera diff A B`: reads two images through OpenImageIO into 8-bit code units (an 8-bit file's
// codes as stored, a float or half file's values x 255) and prints max and mean abs difference,
// RMSE, PSNR, the count of differing pixels, for two float files the largest distance in float32
// ULPs, and on request a heat-map image of the difference. PSNR follows the usual definition,
// 20 log10(255 / RMSE) dB (infinite for identical images).
#include "commands.h"

#include "arg_cursor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <tessera/buffers/surface.h>
#include <tessera/inspect/buffer_view.h>
#include <tessera/io/image_writer.h>
#include <tessera/errors/input_error.h>

#if !defined(TESSERA_NO_OIIO) && __has_include(<OpenImageIO/imageio.h>)
#define TESSERA_DIFF_HAS_OIIO 1
#include <OpenImageIO/imageio.h>
#endif

namespace tessera::cli {
namespace {

constexpr const char* kDiffUsage = R"(usage: tessera diff A B [options]

Compares two images of the same size and channel count (PNG 8-bit, EXR half or float, or any
format OpenImageIO reads) channel by channel. All figures are in 8-bit code units: an 8-bit file's
codes as stored, any other file's values x 255 (an EXR value of 1.0 is code 255), so a max abs of
1 is one code step. Prints:
  max abs    the largest |A - B| over all pixels and channels (x255)
  mean abs   the mean |A - B| over all pixels and channels (x255)
  rmse       the root mean square of (A - B) x 255 over all pixels and channels
  psnr       20 log10(255 / rmse) in dB ("inf" when the images are equal)
  differing  pixels with any channel differing by more than the threshold (default 0: any)
  max ulp    (both files float, e.g. EXR dumps) the largest distance between the two float32
             values of a channel, in units in the last place (0: identical bits; 1: neighbours)

options:
  --json           print one JSON object instead (psnr_db is null when the images are equal)
  --ignore-alpha   leave out each image's alpha channel (e.g. a presented PNG, alpha 255,
                   against a dumped buffer that keeps the stored alpha)
  --threshold T    a pixel differs when a channel differs by more than T code units (default 0)
  --heatmap FILE   also write FILE (.png): each pixel's largest channel difference on a heat ramp,
                   black (equal) through blue, green, yellow to white (the max abs)
  --help           show this text

Exit codes: 0 compared (equal or not), 2 bad usage, an unreadable file, or images whose sizes
or channel counts differ (the message names both files).
)";

struct Image {
    int width = 0, height = 0, channels = 0, alpha = -1;  // alpha: channel index, -1 none
    std::vector<std::string> channelNames;
    std::vector<double> codes;  // row-major, interleaved, in 8-bit code units (value x 255)
    bool floats = false;        // read as float32 (not 8-bit): codes / 255 is the float exactly
};

#ifdef TESSERA_DIFF_HAS_OIIO
Image readImage(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": no such file");
    // PNG readers premultiply colour by alpha unless told the file's alpha is unassociated
    // (as tessera writes it): compare the stored values.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) throw InputError(path + ": cannot read the image: " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.deep) throw InputError(path + ": deep images are not supported");
    if (spec.depth > 1) throw InputError(path + ": volume images are not supported");
    Image img;
    img.width = spec.width;
    img.height = spec.height;
    img.channels = spec.nchannels;
    img.alpha = spec.alpha_channel;
    img.channelNames = spec.channelnames;
    const std::size_t samples = std::size_t(img.width) * std::size_t(img.height) * std::size_t(img.channels);
    // 8-bit files keep their integer codes, so 8-bit against 8-bit differences are exact integers;
    // everything else is read as float and scaled by 255 in double.
    const bool bytes = spec.format == OIIO::TypeDesc::UINT8;
    std::vector<unsigned char> codes8(bytes ? samples : 0);
    std::vector<float> values(bytes ? 0 : samples);
    const bool ok = bytes ? in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::UINT8, codes8.data())
                          : in->read_image(0, 0, 0, img.channels, OIIO::TypeDesc::FLOAT, values.data());
    if (!ok) {
        const std::string err = in->geterror();
        throw InputError(path + ": cannot decode the image: " + (err.empty() ? std::string("unknown error") : err));
    }
    in->close();
    img.floats = !bytes;
    img.codes.resize(samples);
    for (std::size_t i = 0; i < samples; ++i) img.codes[i] = bytes ? double(codes8[i]) : double(values[i]) * 255.0;
    return img;
}
#else
Image readImage(const std::string& path) {
    throw std::runtime_error(path + ": this tessera was built without OpenImageIO (TESSERA_WITH_OIIO=OFF) and reads no images");
}
#endif

// The channel indices compared: all, or all but alpha.
std::vector<int> comparedChannels(const Image& img, bool ignoreAlpha) {
    std::vector<int> channels;
    for (int c = 0; c < img.channels; ++c)
        if (!(ignoreAlpha && c == img.alpha)) channels.push_back(c);
    return channels;
}

std::string channelCount(std::size_t n) { return std::to_string(n) + (n == 1 ? " channel" : " channels"); }

std::string channelList(const Image& img, const std::vector<int>& channels) {
    std::string s;
    for (const int c : channels) {
        if (!s.empty()) s += ",";
        s += std::size_t(c) < img.channelNames.size() && !img.channelNames[std::size_t(c)].empty() ? img.channelNames[std::size_t(c)]
                                                                                                   : std::to_string(c);
    }
    return s;
}

// Distance in float32 ULPs: the bit patterns mapped to a monotonic integer line (negative floats
// mirrored below +0, so -0 and +0 are one point) and subtracted. NaN against anything: none.
std::uint64_t ulpDistance(float a, float b) {
    const auto line = [](float f) {
        std::uint32_t bits = 0;
        std::memcpy(&bits, &f, 4);
        const std::int64_t magnitude = std::int64_t(bits & 0x7FFFFFFFu);
        return (bits >> 31) ? -magnitude : magnitude;
    };
    const std::int64_t d = line(a) - line(b);
    return std::uint64_t(d < 0 ? -d : d);
}

struct Result {
    double maxAbs = 0.0;  // code units
    double meanAbs = 0.0; // code units
    std::uint64_t maxUlp = 0;  // both images float: the largest float32 ULP distance of a channel pair
    double rmse = 0.0;    // code units
    double psnr = std::numeric_limits<double>::infinity();
    std::uint64_t differing = 0;
    std::uint64_t nonFinite = 0;  // pixels where a channel pair is NaN/inf on one side only (left out of the sums)
};

Result compare(const Image& a, const std::vector<int>& chA, const Image& b, const std::vector<int>& chB, double threshold,
               std::vector<double>* pixelMax) {
    Result r;
    double sumSquares = 0.0, sumAbs = 0.0;
    const bool floats = a.floats && b.floats;
    if (pixelMax) pixelMax->assign(std::size_t(a.width) * std::size_t(a.height), 0.0);
    std::uint64_t samples = 0;
    const std::size_t pixels = std::size_t(a.width) * std::size_t(a.height);
    for (std::size_t p = 0; p < pixels; ++p) {
        bool differs = false, nonFinite = false;
        for (std::size_t i = 0; i < chA.size(); ++i) {
            const double va = a.codes[p * std::size_t(a.channels) + std::size_t(chA[i])];
            const double vb = b.codes[p * std::size_t(b.channels) + std::size_t(chB[i])];
            if (va == vb || (std::isnan(va) && std::isnan(vb))) {
                ++samples;
                continue;
            }
            // codes = float * 255 exactly in double, so / 255 gives the stored float back.
            if (floats && !std::isnan(va) && !std::isnan(vb))
                r.maxUlp = std::max(r.maxUlp, ulpDistance(float(va / 255.0), float(vb / 255.0)));
            const double d = std::abs(va - vb);
            if (!std::isfinite(d)) {
                nonFinite = differs = true;
                continue;
            }
            ++samples;
            sumSquares += d * d;
            sumAbs += d;
            if (d > r.maxAbs) r.maxAbs = d;
            if (pixelMax) (*pixelMax)[p] = std::max((*pixelMax)[p], d);
            if (d > threshold) differs = true;
        }
        r.differing += differs ? 1 : 0;
        r.nonFinite += nonFinite ? 1 : 0;
    }
    r.rmse = samples ? std::sqrt(sumSquares / double(samples)) : 0.0;
    r.meanAbs = samples ? sumAbs / double(samples) : 0.0;
    if (r.rmse > 0.0) r.psnr = 20.0 * std::log10(255.0 / r.rmse);
    return r;
}

struct DiffUsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

} // namespace

int diffCommand(const std::vector<std::string_view>& args) {
    std::vector<std::string> files;
    bool json = false, ignoreAlpha = false;
    std::string heatmap;
    double threshold = 0.0;
    try {
        ArgCursor cursor(args);
        while (cursor.next()) {
            const std::string_view a = cursor.flag();
            if (a == "--help" || a == "-h") {
                std::fputs(kDiffUsage, stdout);
                return 0;
            }
            if (a == "--json") json = true;
            else if (a == "--ignore-alpha") ignoreAlpha = true;
            else if (a == "--heatmap") {
                heatmap = std::string(cursor.value());
                if (std::filesystem::path(heatmap).extension() != ".png")
                    throw DiffUsageError("--heatmap: '" + heatmap + "' must end in .png");
            }
            else if (a == "--threshold") {
                const std::string text(cursor.value());
                std::size_t used = 0;
                try {
                    threshold = std::stod(text, &used);
                } catch (const std::exception&) {
                    used = 0;
                }
                if (used != text.size() || !(threshold >= 0.0) || !std::isfinite(threshold))
                    throw DiffUsageError("--threshold: '" + text + "' is not a number >= 0 (8-bit code units)");
            } else if (cursor.isOption()) throw DiffUsageError("unknown option '" + std::string(a) + "'");
            else files.emplace_back(a);
        }
        if (files.size() != 2)
            throw DiffUsageError("diff needs two images, got " + std::to_string(files.size()) +
                                 (files.empty() ? std::string() : " ('" + files[0] + (files.size() > 1 ? "', ...)" : "')")));
    } catch (const DiffUsageError& e) {
        std::fprintf(stderr, "tessera diff: %s (see tessera diff --help)\n", e.what());
        return 2;
    } catch (const UsageError& e) {  // the argument loop's ("--threshold needs a value")
        std::fprintf(stderr, "tessera diff: %s (see tessera diff --help)\n", e.what());
        return 2;
    }

    const Image a = readImage(files[0]);
    const Image b = readImage(files[1]);
    if (a.width != b.width || a.height != b.height)
        throw InputError("cannot compare " + files[0] + " (" + std::to_string(a.width) + "x" + std::to_string(a.height) + ") with " +
                         files[1] + " (" + std::to_string(b.width) + "x" + std::to_string(b.height) + "): the sizes differ");
    const std::vector<int> chA = comparedChannels(a, ignoreAlpha), chB = comparedChannels(b, ignoreAlpha);
    if (chA.size() != chB.size())
        throw InputError("cannot compare " + files[0] + " (" + channelCount(chA.size()) + ": " + channelList(a, chA) + ") with " +
                         files[1] + " (" + channelCount(chB.size()) + ": " + channelList(b, chB) +
                         "): the channel counts differ" + (ignoreAlpha ? "" : " (--ignore-alpha leaves out alpha channels)"));

    std::vector<double> pixelMax;
    const Result r = compare(a, chA, b, chB, threshold, heatmap.empty() ? nullptr : &pixelMax);
    if (!heatmap.empty()) {
        Surface image({std::uint32_t(a.width), std::uint32_t(a.height), Format::R8G8B8A8_UNORM, 1});
        for (std::uint32_t y = 0; y < image.height(); ++y)
            for (std::uint32_t x = 0; x < image.width(); ++x) {
                const double d = pixelMax[std::size_t(y) * image.width() + x];
                const std::uint32_t rgba = heatColor(r.maxAbs > 0.0 ? float(d / r.maxAbs) : 0.0f) | 0xFF000000u;
                std::memcpy(image.texel(x, y), &rgba, 4);
            }
        writeSurface(image, heatmap);
    }
    const std::uint64_t pixels = std::uint64_t(a.width) * std::uint64_t(a.height);
    if (json) {
        nlohmann::ordered_json j;
        j["a"] = files[0];
        j["b"] = files[1];
        j["width"] = a.width;
        j["height"] = a.height;
        j["channels"] = chA.size();
        j["channel_names"] = channelList(a, chA);
        j["units"] = "8-bit code units (8-bit files as stored, other values x 255)";
        j["max_abs"] = r.maxAbs;
        j["mean_abs"] = r.meanAbs;
        j["rmse"] = r.rmse;
        j["psnr_db"] = std::isfinite(r.psnr) ? nlohmann::ordered_json(r.psnr) : nlohmann::ordered_json(nullptr);
        j["threshold"] = threshold;
        j["differing_pixels"] = r.differing;
        j["pixels"] = pixels;
        j["nonfinite_pixels"] = r.nonFinite;
        j["max_ulp"] = a.floats && b.floats ? nlohmann::ordered_json(r.maxUlp) : nlohmann::ordered_json(nullptr);
        if (!heatmap.empty()) j["heatmap"] = heatmap;
        std::printf("%s\n", j.dump().c_str());
    } else {
        std::printf("%s vs %s: %dx%d, %s (%s); figures in 8-bit code units (values x 255)\n", files[0].c_str(),
                    files[1].c_str(), a.width, a.height, channelCount(chA.size()).c_str(),
                    channelList(a, chA).c_str());
        std::printf("max abs    %.6g\n", r.maxAbs);
        std::printf("mean abs   %.6g\n", r.meanAbs);
        std::printf("rmse       %.6g\n", r.rmse);
        if (std::isfinite(r.psnr)) std::printf("psnr       %.3f dB\n", r.psnr);
        else std::printf("psnr       inf dB (equal)\n");
        std::printf("differing  %llu of %llu pixels (%.3f%%)\n", (unsigned long long)r.differing, (unsigned long long)pixels,
                    pixels ? 100.0 * double(r.differing) / double(pixels) : 0.0);
        if (a.floats && b.floats) std::printf("max ulp    %llu (float32)\n", (unsigned long long)r.maxUlp);
        if (!heatmap.empty()) std::printf("heatmap    %s (black: equal; white: %.6g)\n", heatmap.c_str(), r.maxAbs);
        if (r.nonFinite)
            std::printf("nonfinite  %llu pixels with NaN or inf on one side only (differing, left out of max abs and rmse)\n",
                        (unsigned long long)r.nonFinite);
    }
    return 0;
}

} // namespace tessera::cli

// The files a render writes (render_output.h).
#include "render_output.h"

#include <span>

#include <tessera/inspect/buffer_view.h>
#include <tessera/io/atomic_file.h>
#include <tessera/io/image_writer.h>
#include <tessera/techniques/technique.h>

namespace tessera::cli {

namespace fs = std::filesystem;

std::string decodeRule(tessera::Format format, const std::string& file) {
    const tessera::FormatInfo& info = tessera::formatInfo(format);
    const std::string name(info.name);
    if (info.hasDepth)
        return name + ": depth as float32 in " + file + " (D24: code / (2^24 - 1), exact in float32); stencil codes 0..255 in the .stencil.png";
    if (format == tessera::Format::R8G8B8A8_UNORM) return name + ": the stored bytes; value = code / 255";
    if (format == tessera::Format::R8G8B8A8_UNORM_SRGB) return name + ": the stored bytes; RGB decode sRGB -> linear, A = code / 255";
    if (info.kind == tessera::FormatKind::Uint) return name + ": uint32 per channel as stored (TIFF)";
    return name + ": each channel decoded to float32 (EXR), the value a shader Load returns";
}

void dumpRegistry(const tessera::BufferRegistry& registry, const fs::path& dir, const RenderOptions& o, bool views,
                  std::vector<WrittenFile>& written, nlohmann::json& buffers) {
    fs::create_directories(dir);
    if (views) fs::create_directories(dir / "view");
    for (const std::string& name : registry.names()) {
        const tessera::Surface& s = *registry.find(name);
        const std::string file = name + tessera::losslessExtension(s.format());
        written.push_back({(dir / file).string(), tessera::writeSurface(s, dir / file)});
        nlohmann::json entry{{"name", name},
                             {"format", std::string(tessera::formatInfo(s.format()).name)},
                             {"width", s.width()},
                             {"height", s.height()},
                             {"samples", s.sampleCount()},
                             {"file", file},
                             {"decode", decodeRule(s.format(), file)}};
        if (tessera::formatInfo(s.format()).hasStencil) {
            const std::string stencil = name + ".stencil.png";
            written.push_back({(dir / stencil).string(), tessera::writeStencil(s, dir / stencil)});
            entry["stencilFile"] = stencil;
        }
        if (views) {
            nlohmann::json viewEntries = nlohmann::json::array();
            const auto addView = [&](tessera::ViewChannel channel, const std::string& suffix) {
                const auto view = tessera::viewBuffer(name, s, channel, o.exposure);
                if (!view) return;
                const std::string viewFile = "view/" + name + suffix + ".png";
                written.push_back({(dir / viewFile).string(), tessera::writeSurface(view->image, dir / viewFile)});
                viewEntries.push_back({{"file", viewFile}, {"rule", view->rule}});
            };
            addView(tessera::ViewChannel::Depth, "");
            if (tessera::formatInfo(s.format()).hasStencil) addView(tessera::ViewChannel::Stencil, ".stencil");
            if (name.rfind("gbuffer.", 0) == 0) {
                addView(tessera::ViewChannel::Rgb, ".rgb");      // the colour without the data in alpha
                addView(tessera::ViewChannel::Alpha, ".alpha");  // opacity, packed power, specular intensity
            }
            // Light counts over the image (the tiled techniques' grids; --tile-size of the technique).
            const tessera::Surface* back = registry.find(tessera::kBackBufferName);
            if (name.rfind("lightgrid", 0) == 0 && back && o.viewTileSize)
                if (const auto overlay = tessera::overlayTileCounts(s, o.viewTileSize, *back)) {
                    const std::string viewFile = "view/" + name + ".overlay.png";
                    written.push_back({(dir / viewFile).string(), tessera::writeSurface(overlay->image, dir / viewFile)});
                    viewEntries.push_back({{"file", viewFile}, {"rule", overlay->rule}});
                }
            if (!viewEntries.empty()) entry["views"] = viewEntries;
        }
        buffers.push_back(entry);
    }
}

tessera::Surface outputImage(const tessera::BufferRegistry& registry, const std::string& out) {
    const tessera::Surface& back = *registry.find(tessera::kBackBufferName);
    const tessera::Surface* reference = registry.find(tessera::kReferenceBufferName);
    if (!reference) return back;
    if (fs::path(out).extension() == ".exr") return *reference;
    tessera::Surface rounded(back.desc());
    tessera::storeAsUnorm(*reference, rounded);
    return rounded;
}

std::vector<WrittenFile> writeOutputs(const tessera::BufferRegistry& registry, const RenderOptions& o, nlohmann::json manifest,
                                      DumpStaging* staging) {
    std::vector<WrittenFile> written;
    if (o.noOutput) return written;
    const tessera::Surface image = outputImage(registry, o.out);
    if (o.dumpDir.empty()) {
        written.push_back({o.out, tessera::writeSurface(image, o.out, o.exrType)});
        return written;
    }
    nlohmann::json buffers = nlohmann::json::array();
    dumpRegistry(registry, o.dumpDir, o, true, written, buffers);
    manifest["buffers"] = buffers;
    manifest["image"] = o.out;
    // Paths and the command line are bytes, not necessarily UTF-8: those bytes become U+FFFD in
    // the manifest (a plain dump() throws on them, after every image was written).
    const std::string text = manifest.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    const fs::path manifestFile = fs::path(o.dumpDir) / "manifest.json";
    tessera::writeFileAtomically(manifestFile, std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()));
    written.push_back({manifestFile.string(), tessera::fnv1a64(std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()))});
    // The image after the dump, and the dump moved into place last: a failure before leaves neither.
    written.insert(written.begin(), WrittenFile{o.out, tessera::writeSurface(image, o.out, o.exrType)});
    if (staging) staging->commit();
    return written;
}

void printHashes(const std::vector<WrittenFile>& written, const DumpStaging* staging) {
    for (const WrittenFile& w : written)
        std::printf("hash     %s  %s\n", tessera::hashHex(w.hash).c_str(),
                    (staging ? staging->finalPath(w.path) : w.path).c_str());
}

} // namespace tessera::cli

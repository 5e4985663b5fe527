// BufferRegistry: name -> Surface, in registration order; storage kept across clear() for reuse.
#include <tessera/frame/buffer_registry.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include <tessera/frame/memory_limit.h>

namespace tessera {

namespace {

bool sameDesc(const SurfaceDesc& a, const SurfaceDesc& b) {
    return a.width == b.width && a.height == b.height && a.format == b.format && a.sampleCount == b.sampleCount;
}

} // namespace

Surface& BufferRegistry::create(const std::string& name, const SurfaceDesc& desc) {
    if (Surface* s = find(name)) {
        if (!sameDesc(s->desc(), desc))
            throw std::invalid_argument("buffer '" + name + "' already exists with a different size, format or sample count");
        return *s;
    }
    // width, height <= 16384, samples <= 8, 16 B per texel: at most 2^35 B, no overflow.
    const std::uint64_t bytes = std::uint64_t(desc.width) * desc.height * desc.sampleCount * formatInfo(desc.format).bytesPerTexel;
    if (bytes > mByteLimit || mBytes > mByteLimit - bytes)
        throw MemoryLimitError("buffer '" + name + "' (" + std::to_string(desc.width) + "x" + std::to_string(desc.height) +
                               (desc.sampleCount > 1 ? " x" + std::to_string(desc.sampleCount) + " samples" : "") + ", " +
                               std::string(formatInfo(desc.format).name) + ", " + formatBytes(double(bytes)) +
                               ") would take the frame's buffers to " + formatBytes(double(mBytes + bytes)) +
                               ", past the memory limit of " + formatBytes(double(mByteLimit)) +
                               (mLimitHint.empty() ? "" : " (" + mLimitHint + ")"));
    std::unique_ptr<Surface> surface;
    const auto spare = std::find_if(mSpare.begin(), mSpare.end(), [&](const std::unique_ptr<Surface>& s) { return sameDesc(s->desc(), desc); });
    if (spare != mSpare.end()) {
        surface = std::move(*spare);
        mSpare.erase(spare);
        std::memset(surface->bytes().data(), 0, surface->bytes().size());  // as a new Surface starts
    } else {
        // Spares are kept only while they, the live buffers and this one fit under the limit, so
        // that the process never holds more buffer memory than the limit allows.
        if (spareBytes() > mByteLimit - mBytes - bytes) mSpare.clear();
        surface = std::make_unique<Surface>(desc);
    }
    mBytes += bytes;
    Surface& ref = *surface;
    mBuffers.emplace(name, std::move(surface));
    mOrder.push_back(name);
    return ref;
}

void BufferRegistry::clear() {
    mSpare.clear();  // kept at the last clear() and not reused by this frame
    for (auto& [name, surface] : mBuffers) mSpare.push_back(std::move(surface));
    mBuffers.clear();
    mOrder.clear();
    mBytes = 0;
}

std::uint64_t BufferRegistry::spareBytes() const {
    std::uint64_t bytes = 0;
    for (const std::unique_ptr<Surface>& s : mSpare) bytes += s->bytes().size();
    return bytes;
}

void BufferRegistry::setByteLimit(std::uint64_t bytes, std::string hint) {
    mByteLimit = bytes;
    mLimitHint = std::move(hint);
}

Surface* BufferRegistry::find(std::string_view name) {
    const auto it = mBuffers.find(name);
    return it == mBuffers.end() ? nullptr : it->second.get();
}

const Surface* BufferRegistry::find(std::string_view name) const {
    const auto it = mBuffers.find(name);
    return it == mBuffers.end() ? nullptr : it->second.get();
}

Surface& BufferRegistry::get(std::string_view name) {
    if (Surface* s = find(name)) return *s;
    throw std::out_of_range("no buffer named '" + std::string(name) + "'");
}

} // namespace tessera

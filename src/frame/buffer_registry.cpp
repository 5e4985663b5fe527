// BufferRegistry: name -> Surface, in registration order.
#include <tessera/frame/buffer_registry.h>

#include <stdexcept>

#include <tessera/frame/memory_limit.h>

namespace tessera {

Surface& BufferRegistry::create(const std::string& name, const SurfaceDesc& desc) {
    if (Surface* s = find(name)) {
        const SurfaceDesc& d = s->desc();
        if (d.width != desc.width || d.height != desc.height || d.format != desc.format || d.sampleCount != desc.sampleCount)
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
    auto surface = std::make_unique<Surface>(desc);
    mBytes += bytes;
    Surface& ref = *surface;
    mBuffers.emplace(name, std::move(surface));
    mOrder.push_back(name);
    return ref;
}

void BufferRegistry::clear() {
    mBuffers.clear();
    mOrder.clear();
    mBytes = 0;
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

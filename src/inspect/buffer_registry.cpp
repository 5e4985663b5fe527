// BufferRegistry: name -> Surface, in registration order.
#include <tessera/inspect/buffer_registry.h>

#include <stdexcept>

namespace tessera {

Surface& BufferRegistry::create(const std::string& name, const SurfaceDesc& desc) {
    if (Surface* s = find(name)) {
        const SurfaceDesc& d = s->desc();
        if (d.width != desc.width || d.height != desc.height || d.format != desc.format || d.sampleCount != desc.sampleCount)
            throw std::invalid_argument("buffer '" + name + "' already exists with a different size, format or sample count");
        return *s;
    }
    auto surface = std::make_unique<Surface>(desc);
    Surface& ref = *surface;
    mBuffers.emplace(name, std::move(surface));
    mOrder.push_back(name);
    return ref;
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

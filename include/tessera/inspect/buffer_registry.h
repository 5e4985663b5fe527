// Named buffers: every surface a pass writes is registered here under a name ("gbuffer.normal",
// "depth", "backbuffer"), so that later passes, tests, --dump and the inspector can find it.
// Names are kept in registration order; a buffer's address is stable for the registry's life.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <tessera/buffers/surface.h>

namespace tessera {

class BufferRegistry {
public:
    // Creates (or, if `name` exists with the same desc, returns) a surface. Throws
    // std::invalid_argument naming the buffer when it exists with a different desc.
    Surface& create(const std::string& name, const SurfaceDesc& desc);
    // nullptr when absent.
    Surface* find(std::string_view name);
    const Surface* find(std::string_view name) const;
    // Throws std::out_of_range naming the buffer when absent.
    Surface& get(std::string_view name);
    bool contains(std::string_view name) const { return find(name) != nullptr; }
    const std::vector<std::string>& names() const { return mOrder; }

private:
    std::map<std::string, std::unique_ptr<Surface>, std::less<>> mBuffers;
    std::vector<std::string> mOrder;
};

} // namespace tessera

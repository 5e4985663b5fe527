// Named buffers: every surface a pass writes is registered here under a name ("gbuffer.normal",
// "depth", "backbuffer"), so that later passes, tests, --dump and the inspector can find it.
// Names are kept in registration order; a buffer's address is stable until clear(). clear() keeps
// the buffers' storage for the next frame, as a renderer keeps its render targets: a buffer created
// again with the same size and format reuses it (zeroed, as a new one), instead of faulting in
// fresh pages every frame.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <tessera/buffers/surface.h>

namespace tessera {

class BufferRegistry {
public:
    // Creates (or, if `name` exists with the same desc, returns) a surface, all bytes zero. Throws
    // std::invalid_argument naming the buffer when it exists with a different desc, and
    // MemoryLimitError (frame/memory_limit.h) naming it, its size and the limit, before
    // allocating, when the registry's buffers would pass the byte limit.
    Surface& create(const std::string& name, const SurfaceDesc& desc);
    // The most bytes the registry's buffers may hold together (default: no limit); `hint` ends
    // the error message (how to raise it).
    void setByteLimit(std::uint64_t bytes, std::string hint = {});
    // Drops every buffer (a fresh frame's registry); the byte limit and its hint stay. The dropped
    // buffers' storage is kept for create() to reuse; storage that was kept at the previous clear()
    // and not reused since is freed, so at most one frame's worth is held beyond the live buffers,
    // and create() frees every spare before a new buffer would take live + spare past the limit.
    void clear();
    // Bytes of storage kept by clear() and not reused yet (not counted in bytes() or the limit).
    std::uint64_t spareBytes() const;
    // Bytes held by every buffer (texel storage).
    std::uint64_t bytes() const { return mBytes; }
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
    std::vector<std::unique_ptr<Surface>> mSpare;  // storage clear() kept, for create() to reuse
    std::uint64_t mBytes = 0, mByteLimit = ~std::uint64_t{0};
    std::string mLimitHint;
};

} // namespace tessera

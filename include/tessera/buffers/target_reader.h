// Fast Texture2D.Load (mip 0) of a render target that a later pass reads as a texture (G-buffers,
// light accumulation): R8G8B8A8_UNORM through a 256-entry table made by the format's own decoder
// (so the values are decodeTexel's), R32G32B32A32_FLOAT as stored, anything else by Surface::load.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <glm/glm.hpp>

#include <tessera/buffers/surface.h>
#include <tessera/buffers/texel_codec.h>

namespace tessera {

class TargetReader {
public:
    TargetReader() = default;
    explicit TargetReader(const Surface& s) : mSurface(&s), mRgba8(s.format() == Format::R8G8B8A8_UNORM) {
        for (unsigned c = 0; c < 256 && mRgba8; ++c) {
            const std::array<std::byte, 4> texel{std::byte(c), std::byte(0), std::byte(0), std::byte(0)};
            mUnorm8[c] = decodeTexel(Format::R8G8B8A8_UNORM, texel.data()).x;
        }
    }
    // Sample `sample` of texel (x, y) (Texture2DMS.Load); the caller keeps x, y and the sample
    // inside the surface.
    glm::vec4 load(std::uint32_t x, std::uint32_t y, std::uint32_t sample = 0) const {
        const std::byte* p = mSurface->texel(x, y, sample);
        if (mRgba8)
            return {mUnorm8[std::to_integer<unsigned>(p[0])], mUnorm8[std::to_integer<unsigned>(p[1])],
                    mUnorm8[std::to_integer<unsigned>(p[2])], mUnorm8[std::to_integer<unsigned>(p[3])]};
        if (mSurface->format() == Format::R32G32B32A32_FLOAT) {
            glm::vec4 v;
            std::memcpy(&v[0], p, sizeof v);
            return v;
        }
        return mSurface->load(x, y, sample);
    }

private:
    const Surface* mSurface = nullptr;
    bool mRgba8 = false;
    std::array<float, 256> mUnorm8{};  // UNORM8 code -> value
};

} // namespace tessera

// Unit tests for Texture2D and texture sampling (D3D11.3 §7.18): every expected number is
// derived by hand beside it — texel addressing, address modes, border colour, LOD selection and
// clamps, trilinear weights, the mip filter (odd sizes too), sRGB decoding before filtering,
// Load's out-of-range rule and the InputError raised for bad images.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <tessera/buffers/conversion.h>
#include <tessera/errors/input_error.h>
#include <tessera/texture/sampling.h>
#include <tessera/texture/texture2d.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::texture_texture_test {

using namespace tessera;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
const float kNaN = std::bit_cast<float>(0x7FC00000u);

Image makeImage(std::uint32_t width, std::uint32_t height, std::vector<std::uint8_t> rgba8,
                std::string source = "test.png") {
    Image image;
    image.width = width;
    image.height = height;
    image.rgba8 = std::move(rgba8);
    image.source = std::move(source);
    return image;
}

// 4x4 float texture whose texel (x, y) is (x, y, 10y + x, 1): a filtered R is a texel-space x,
// a filtered G a texel-space y. Full chain: 4x4, 2x2, 1x1.
Texture2D gridTexture() {
    std::vector<float> rgba;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            rgba.insert(rgba.end(), {float(x), float(y), float(10 * y + x), 1.0f});
    return Texture2D::fromFloatRgba(4, 4, rgba, "grid");
}

// A 64x64 (or w x h) float texture of zeros: only its size matters for LOD tests.
Texture2D blankTexture(std::uint32_t width, std::uint32_t height) {
    return Texture2D::fromFloatRgba(width, height, std::vector<float>(std::size_t(width) * height * 4, 0.0f), "blank");
}

SamplerState makeSampler(Filter minMag, Filter mip, AddressMode address) {
    SamplerState s;
    s.minFilter = s.magFilter = minMag;
    s.mipFilter = mip;
    s.addressU = s.addressV = address;
    return s;
}

std::uint8_t byteAt(const Texture2D& texture, int level, std::size_t index) {
    return std::to_integer<std::uint8_t>(texture.levelBytes(level)[index]);
}

template <class F> std::string thrownMessage(F&& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "<no InputError>";
}

} // namespace

TEST_CASE("texture: mip chain sizes follow D3D11: max(1, floor(size / 2^level))") {
    const Texture2D t = Texture2D::fromImage(makeImage(5, 3, std::vector<std::uint8_t>(5 * 3 * 4, 0)), TexelEncoding::Linear);
    REQUIRE(t.levels() == 3);  // 1 + floor(log2(5)) = 3
    CHECK(t.width(0) == 5);
    CHECK(t.height(0) == 3);
    CHECK(t.width(1) == 2);   // floor(5/2)
    CHECK(t.height(1) == 1);  // floor(3/2)
    CHECK(t.width(2) == 1);   // floor(5/4)
    CHECK(t.height(2) == 1);  // max(1, floor(3/4) = 0)
    CHECK(t.width(3) == 0);   // no such level (resinfo's out-of-range answer)
    CHECK(t.memoryBytes() == (15u + 2u + 1u) * 4u);  // texels of all levels x 4 bytes = 72
    CHECK(t.levelBytes(1).size() == 2 * 4);
    CHECK(t.levelBytes(3).empty());
    CHECK(t.format() == Format::R8G8B8A8_UNORM);

    const Texture2D grid = gridTexture();
    CHECK(grid.levels() == 3);  // 4, 2, 1
    CHECK(grid.format() == Format::R32G32B32A32_FLOAT);
    CHECK(grid.memoryBytes() == (16u + 4u + 1u) * 16u);  // 336

    const Texture2D noMips = Texture2D::fromImage(makeImage(4, 4, std::vector<std::uint8_t>(64, 7)),
                                                  TexelEncoding::Srgb, /*generateMips=*/false);
    CHECK(noMips.levels() == 1);
    CHECK(noMips.memoryBytes() == 64);
    CHECK(noMips.format() == Format::R8G8B8A8_UNORM_SRGB);

    CHECK(blankTexture(16384, 1).levels() == 15);  // 1 + log2(16384)
    CHECK(blankTexture(16384, 1).width(14) == 1);
    CHECK(blankTexture(1, 1).levels() == 1);
}

TEST_CASE("texture: point and bilinear sampling on a 4x4 texture at known uv (§7.18.7, §7.18.8)") {
    const Texture2D grid = gridTexture();
    const SamplerState point = makeSampler(Filter::Point, Filter::Point, AddressMode::Clamp);
    const SamplerState linear = makeSampler(Filter::Linear, Filter::Point, AddressMode::Clamp);

    // Point: texel = floor(u * 4). (0.3125, 0.5625) -> floor(1.25), floor(2.25) = (1, 2).
    CHECK(sampleLevel(grid, point, {0.3125f, 0.5625f}, 0.0f) == glm::vec4(1, 2, 21, 1));
    // (0.375, 0.125) -> floor(1.5), floor(0.5) = (1, 0).
    CHECK(sampleLevel(grid, point, {0.375f, 0.125f}, 0.0f) == glm::vec4(1, 0, 1, 1));

    // Bilinear: s = u * 4 - 0.5. u = 0.3125: s = 0.75 -> texels 0, 1, wCeil 0.75 -> R 0.75.
    // v = 0.5625: s = 1.75 -> rows 1, 2, wCeil 0.75 -> G = 1 + (2 - 1) * 0.75 = 1.75.
    // B: row 1: 10 + (11 - 10) * 0.75 = 10.75; row 2: 20.75; 10.75 + 10 * 0.75 = 18.25.
    CHECK(sampleLevel(grid, linear, {0.3125f, 0.5625f}, 0.0f) == glm::vec4(0.75f, 1.75f, 18.25f, 1.0f));
    // At a texel centre (0.375, 0.625): s = (1, 2) exactly, weights 0 -> texel (1, 2) itself.
    CHECK(sampleLevel(grid, linear, {0.375f, 0.625f}, 0.0f) == glm::vec4(1, 2, 21, 1));
    // Point sampling returns exactly what Load returns, texel by texel.
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            CHECK(sampleLevel(grid, point, {(float(x) + 0.5f) / 4.0f, (float(y) + 0.5f) / 4.0f}, 0.0f) ==
                  grid.load({x, y}));

    // UNORM: codes 51 and 102 decode to 51/255 = 0.2 and 102/255 = 0.4 (§3.2.3.5); halfway
    // (u = 0.5 on a 2x1 texture: s = 1 - 0.5 = 0.5) gives 0.2f + (0.4f - 0.2f) * 0.5f ~ 0.3.
    const Texture2D unorm = Texture2D::fromImage(makeImage(2, 1, {51, 0, 0, 255, 102, 0, 0, 255}), TexelEncoding::Linear);
    const float r51 = convert::unormToFloat(51, 8), r102 = convert::unormToFloat(102, 8);
    const glm::vec4 mid = sampleLevel(unorm, linear, {0.5f, 0.5f}, 0.0f);
    CHECK(mid.x == r51 + (r102 - r51) * 0.5f);
    CHECK(mid.x == doctest::Approx(0.3));
    CHECK(mid.w == 1.0f);
}

TEST_CASE("texture: address modes at and beyond the edges, point sampling (§7.18.6, §7.18.9)") {
    const Texture2D grid = gridTexture();  // R = column index; v = 0.125 stays on row 0
    struct Case {
        float u;
        float wrap, mirror, clamp, mirrorOnce;  // expected column (R)
        bool border;                            // Border: off the texture -> border colour
        const char* why;
    };
    const std::vector<Case> cases = {
        // u = -0.25: Wrap frac -> 0.75 -> floor(3.0) = 3. Others: floor(-1.0) = -1 -> Mirror and
        // MirrorOnce -(-1) - 1 = 0, Clamp 0, Border off.
        {-0.25f, 3, 0, 0, 0, true, "u = -0.25: texel -1"},
        {0.0f, 0, 0, 0, 0, false, "u = 0: texel 0"},
        // u = 1: Wrap frac(1) = 0 -> 0. Mirror: reduced 1 -> texel 4: odd tile (4/4 = 1), 4 % 4 = 0
        // -> 4 - 0 - 1 = 3. Clamp/MirrorOnce 3. Border off.
        {1.0f, 0, 3, 3, 3, true, "u = 1: texel 4"},
        // u = 1.25: Wrap 0.25 -> 1. Mirror: texel 5, odd tile, 5 % 4 = 1 -> 4 - 1 - 1 = 2.
        {1.25f, 1, 2, 3, 3, true, "u = 1.25: texel 5"},
        // u = -0.3: Wrap frac = 0.7 -> floor(2.8) = 2. Otherwise floor(-1.2) = -2 -> -(-2) - 1 = 1.
        {-0.3f, 2, 1, 0, 1, true, "u = -0.3: texel -2"},
        // Negative wrap: frac(-1.1) = -1.1 + 2 = 0.9 (exact in float) -> floor(3.6) = 3.
        // Mirror: signedFrac(-0.55) * 2 = -1.1 -> floor(-4.4) = -5 -> t = 4, odd tile -> 3.
        // MirrorOnce: -5 -> 4 -> clamp 3. Clamp 0.
        {-1.1f, 3, 3, 0, 3, true, "u = -1.1: texel -5"},
        // Range reduction (§7.18.6) keeps huge u finite: Wrap frac(1e30) = 0 -> 0; Mirror
        // signedFrac(5e29) * 2 = 0 -> 0; Clamp/MirrorOnce reduce to 10 -> texel 40 -> 3.
        {1e30f, 0, 0, 3, 3, true, "u = 1e30"},
        // +INF: Wrap/Mirror reduce to NaN -> texel coordinate 0 (§3.2.4.1); the others to 10.
        {kInf, 0, 0, 3, 3, true, "u = +INF"},
        // NaN: every mode ends on texel coordinate 0.
        {kNaN, 0, 0, 0, 0, false, "u = NaN"},
    };
    const glm::vec4 borderColor(9.0f, 8.0f, 7.0f, 6.0f);
    for (const Case& c : cases) {
        CAPTURE(c.why);
        auto columnFor = [&](AddressMode mode) {
            SamplerState s = makeSampler(Filter::Point, Filter::Point, mode);
            s.borderColor = borderColor;
            return sampleLevel(grid, s, {c.u, 0.125f}, 0.0f);
        };
        CHECK(columnFor(AddressMode::Wrap).x == c.wrap);
        CHECK(columnFor(AddressMode::Mirror).x == c.mirror);
        CHECK(columnFor(AddressMode::Clamp).x == c.clamp);
        CHECK(columnFor(AddressMode::MirrorOnce).x == c.mirrorOnce);
        if (c.border)
            CHECK(columnFor(AddressMode::Border) == borderColor);  // float format: used as given
        else
            CHECK(columnFor(AddressMode::Border).x == c.clamp);
    }

    // The integer rule itself (§7.18.9), size 4.
    CHECK(addressTexel(-1, 4, AddressMode::Wrap) == 3);
    CHECK(addressTexel(-5, 4, AddressMode::Wrap) == 3);      // -5 % 4 = -1 -> + 4
    CHECK(addressTexel(-4, 4, AddressMode::Wrap) == 0);
    CHECK(addressTexel(-1, 4, AddressMode::Mirror) == 0);
    CHECK(addressTexel(-5, 4, AddressMode::Mirror) == 3);    // t = 4: odd tile, 4 - 0 - 1
    CHECK(addressTexel(8, 4, AddressMode::Mirror) == 0);     // t = 8: even tile
    CHECK(addressTexel(-9, 4, AddressMode::MirrorOnce) == 3);  // t = 8 -> clamp
    CHECK(addressTexel(7, 4, AddressMode::Clamp) == 3);
    CHECK(addressTexel(4, 4, AddressMode::Border) == -1);
    CHECK(addressTexel(3, 4, AddressMode::Border) == 3);
}

TEST_CASE("texture: address modes with bilinear taps straddling the edges (§7.18.8, §7.18.9)") {
    const Texture2D grid = gridTexture();
    const glm::vec4 borderColor(9.0f, 8.0f, 7.0f, 6.0f);
    auto sampleAt = [&](float u, AddressMode mode) {
        SamplerState s = makeSampler(Filter::Linear, Filter::Point, mode);
        s.borderColor = borderColor;
        return sampleLevel(grid, s, {u, 0.125f}, 0.0f);  // v: s = 0.5 - 0.5 = 0, row 0 only
    };
    // u = 0: s = -0.5 -> taps -1 and 0, each 0.5.
    CHECK(sampleAt(0.0f, AddressMode::Wrap).x == 1.5f);        // texels 3, 0: 3 + (0 - 3) * 0.5
    CHECK(sampleAt(0.0f, AddressMode::Mirror).x == 0.0f);      // texels 0, 0
    CHECK(sampleAt(0.0f, AddressMode::Clamp).x == 0.0f);       // texels 0, 0
    CHECK(sampleAt(0.0f, AddressMode::MirrorOnce).x == 0.0f);  // texels 0, 0
    // Border: border (9, 8, 7, 6) and texel 0 (0, 0, 0, 1) halfway: (4.5, 4, 3.5, 3.5).
    CHECK(sampleAt(0.0f, AddressMode::Border) == glm::vec4(4.5f, 4.0f, 3.5f, 3.5f));
    // u = 1: s = 3.5 -> taps 3 and 4.
    CHECK(sampleAt(1.0f, AddressMode::Wrap).x == 1.5f);        // frac(1) = 0, as u = 0: texels 3, 0
    CHECK(sampleAt(1.0f, AddressMode::Mirror).x == 3.0f);      // 4 -> 3: texels 3, 3
    CHECK(sampleAt(1.0f, AddressMode::Clamp).x == 3.0f);
    CHECK(sampleAt(1.0f, AddressMode::Border).x == 6.0f);      // 3 + (9 - 3) * 0.5
    // u = 1.25: s = 4.5 -> taps 4, 5 (Wrap reduces to 0.25: s = 0.5, taps 0, 1).
    CHECK(sampleAt(1.25f, AddressMode::Wrap).x == 0.5f);
    CHECK(sampleAt(1.25f, AddressMode::Mirror).x == 2.5f);     // 4 -> 3, 5 -> 2: 3 + (2 - 3) * 0.5
    CHECK(sampleAt(1.25f, AddressMode::Clamp).x == 3.0f);
    CHECK(sampleAt(1.25f, AddressMode::MirrorOnce).x == 3.0f);
    CHECK(sampleAt(1.25f, AddressMode::Border) == borderColor);  // both taps off
    // u = -0.25: s = -1.5 -> taps -2, -1 (Wrap reduces to 0.75: s = 2.5, taps 2, 3).
    CHECK(sampleAt(-0.25f, AddressMode::Wrap).x == 2.5f);
    CHECK(sampleAt(-0.25f, AddressMode::Mirror).x == 0.5f);    // -2 -> 1, -1 -> 0
    CHECK(sampleAt(-0.25f, AddressMode::MirrorOnce).x == 0.5f);
    CHECK(sampleAt(-0.25f, AddressMode::Clamp).x == 0.0f);

    // Border on V only (§7.18.9 "if any single dimension selects Border Color"): U inside.
    SamplerState uClampVBorder = makeSampler(Filter::Point, Filter::Point, AddressMode::Clamp);
    uClampVBorder.addressV = AddressMode::Border;
    uClampVBorder.borderColor = borderColor;
    CHECK(sampleLevel(grid, uClampVBorder, {0.375f, -0.1f}, 0.0f) == borderColor);
    CHECK(sampleLevel(grid, uClampVBorder, {-0.5f, 0.125f}, 0.0f) == glm::vec4(0, 0, 0, 1));  // U clamps
}

TEST_CASE("texture: border colour is clamped to the UNORM range, kept as given for float (§7.18.9.1)") {
    const Texture2D unorm = Texture2D::fromImage(makeImage(2, 2, std::vector<std::uint8_t>(16, 255)), TexelEncoding::Srgb);
    SamplerState s = makeSampler(Filter::Point, Filter::Point, AddressMode::Border);
    s.borderColor = glm::vec4(2.0f, -1.0f, 0.5f, kNaN);
    // R 2 -> 1, G -1 -> 0, B 0.5 stays (linear, not sRGB-decoded), A NaN -> 0.
    CHECK(sampleLevel(unorm, s, {-0.5f, 0.5f}, 0.0f) == glm::vec4(1.0f, 0.0f, 0.5f, 0.0f));
    // Bilinear between border and texel (1, 1, 1, 1) at u = 0 (s = -0.5: taps -1, 0, each 0.5;
    // v = 0.25: s = 0, row 0): (1 + 0) / 2, (0 + 1) / 2, (0.5 + 1) / 2, (0 + 1) / 2.
    s.minFilter = s.magFilter = Filter::Linear;
    CHECK(sampleLevel(unorm, s, {0.0f, 0.25f}, 0.0f) == glm::vec4(1.0f, 0.5f, 0.75f, 0.5f));

    const Texture2D grid = gridTexture();
    SamplerState f = makeSampler(Filter::Point, Filter::Point, AddressMode::Border);
    f.borderColor = glm::vec4(2.0f, -1.0f, 0.5f, 100.0f);
    CHECK(sampleLevel(grid, f, {-0.5f, 0.5f}, 0.0f) == f.borderColor);
}

TEST_CASE("texture: LOD from derivatives: log2 of the longer footprint axis in texels (§7.18.11)") {
    const Texture2D t = blankTexture(64, 64);
    // ddx = (1/64, 0) on 64 texels: |dX| = 1 texel -> log2(1) = 0.
    CHECK(calculateLodUnclamped(t, {1.0f / 64, 0}, {0, 1.0f / 64}) == 0.0f);
    // (4/64, 0): 4 texels -> 2.
    CHECK(calculateLodUnclamped(t, {4.0f / 64, 0}, {0, 4.0f / 64}) == 2.0f);
    // Anisotropic footprint 4 x 1 texels: the larger length wins -> log2(4) = 2.
    CHECK(calculateLodUnclamped(t, {4.0f / 64, 0}, {0, 1.0f / 64}) == 2.0f);
    CHECK(calculateLodUnclamped(t, {1.0f / 64, 0}, {0, 8.0f / 64}) == 3.0f);
    // Diagonal dX = (2, 2) texels: |dX| = sqrt(8) -> log2 = 1.5 exactly.
    CHECK(calculateLodUnclamped(t, {2.0f / 64, 2.0f / 64}, {0, 0}) == 1.5f);
    // dX = (3, 4) texels: |dX| = 5 -> log2(5) = 2.321928...
    CHECK(calculateLodUnclamped(t, {3.0f / 64, 4.0f / 64}, {0, 0}) == doctest::Approx(2.321928094887362).epsilon(1e-7));
    // No footprint: log2(0) = -INF.
    CHECK(calculateLodUnclamped(t, {0, 0}, {0, 0}) == -kInf);

    // Non-square 64 x 16: v derivatives scale by 16. ddy = (0, 1/4) -> 4 texels -> 2.
    const Texture2D wide = blankTexture(64, 16);
    CHECK(calculateLodUnclamped(wide, {1.0f / 64, 0}, {0, 1.0f / 16}) == 0.0f);
    CHECK(calculateLodUnclamped(wide, {1.0f / 64, 0}, {0, 1.0f / 4}) == 2.0f);

    // Powers of two are exact over a wide range; other values agree with libm log2 to ~1 ulp.
    for (int e = -20; e <= 20; ++e)
        CHECK(calculateLodUnclamped(t, {std::ldexp(1.0f, e) / 64, 0}, {0, 0}) == float(e));
    for (float texels = 0.01f; texels < 5000.0f; texels *= 1.37f)
        CHECK(calculateLodUnclamped(t, {texels / 64, 0}, {0, 0}) == doctest::Approx(std::log2(texels)).epsilon(1e-6));
}

// sampling.cpp keeps each thread's last few (size, derivatives) -> LOD results. A fresh thread's
// memo is empty, so there every LOD is computed: the oracle. Here one thread walks a sequence
// whose keys differ from each other in one argument at a time (width, height, each derivative
// component, the sign of a zero, NaN) and repeat at distances below and above the memo's
// capacity; every LOD must equal the cold thread's, bit for bit.
TEST_CASE("texture: a repeated LOD is the LOD computed afresh: the per-thread memo keys on every argument") {
    const Texture2D square = blankTexture(64, 64), tall = blankTexture(64, 128), wide = blankTexture(128, 64);
    const Texture2D* textures[3] = {&square, &tall, &wide};
    const float values[] = {1.0f / 64, 3.0f / 64, -1.0f / 64, 0.0f, -0.0f, 1e-30f, 7.5f, kNaN};
    struct Query {
        const Texture2D* texture;
        glm::vec2 ddx, ddy;
    };
    std::vector<Query> queries;
    std::uint32_t state = 12345u;  // a fixed LCG: the same sequence every run
    auto next = [&](std::uint32_t n) {
        state = state * 1664525u + 1013904223u;
        return (state >> 8) % n;
    };
    for (int i = 0; i < 4000; ++i) {
        if (i < 8) {
            queries.push_back(Query{textures[next(3)], {values[next(8)], values[next(8)]}, {values[next(8)], values[next(8)]}});
            continue;
        }
        // A recent query, 1..8 back (the memo holds 4): repeated as it is, or with one argument changed.
        Query q = queries[queries.size() - 1 - next(8)];
        switch (next(6)) {
        case 0: q.texture = textures[next(3)]; break;
        case 1: q.ddx.x = values[next(8)]; break;
        case 2: q.ddx.y = values[next(8)]; break;
        case 3: q.ddy.x = values[next(8)]; break;
        case 4: q.ddy.y = values[next(8)]; break;
        default: break;
        }
        queries.push_back(q);
    }
    std::vector<float> cold(queries.size());
    for (std::size_t i = 0; i < queries.size(); ++i) {
        std::thread fresh([&] { cold[i] = calculateLodUnclamped(*queries[i].texture, queries[i].ddx, queries[i].ddy); });
        fresh.join();
    }
    for (std::size_t i = 0; i < queries.size(); ++i) {
        const float warm = calculateLodUnclamped(*queries[i].texture, queries[i].ddx, queries[i].ddy);
        INFO("query " << i);
        CHECK(std::bit_cast<std::uint32_t>(warm) == std::bit_cast<std::uint32_t>(cold[i]));
    }
    // The same derivatives on textures of other sizes: 64 x 64 gives 0, 64 x 128 and 128 x 64 give
    // 1 (2 texels along the longer axis), in either order after each other.
    const glm::vec2 ddx{1.0f / 64, 0.0f}, ddy{0.0f, 1.0f / 64};
    CHECK(calculateLodUnclamped(square, ddx, ddy) == 0.0f);
    CHECK(calculateLodUnclamped(tall, ddx, ddy) == 1.0f);
    CHECK(calculateLodUnclamped(wide, ddx, ddy) == 1.0f);
    CHECK(calculateLodUnclamped(square, ddx, ddy) == 0.0f);
}

TEST_CASE("texture: LOD bias and clamps: MipLODBias, MinLOD/MaxLOD, [0, levels - 1] (§7.18.11)") {
    const Texture2D t = blankTexture(64, 64);  // 7 levels: 0..6
    const glm::vec2 lod2{4.0f / 64, 0}, none{0, 0};
    SamplerState s;
    CHECK(calculateLod(t, s, lod2, none) == 2.0f);
    s.mipLodBias = 1.0f;                        // 2 + 1
    CHECK(calculateLod(t, s, lod2, none) == 3.0f);
    s.mipLodBias = 10.0f;                       // 12 -> levels - 1 = 6
    CHECK(calculateLod(t, s, lod2, none) == 6.0f);
    s.mipLodBias = 0.0f;
    s.maxLod = 1.0f;                            // min(1, 2)
    CHECK(calculateLod(t, s, lod2, none) == 1.0f);
    s.maxLod = 3.4e38f;
    s.minLod = 3.0f;                            // max(3, 0)
    CHECK(calculateLod(t, s, {1.0f / 64, 0}, none) == 3.0f);
    s.minLod = 4.0f;
    s.maxLod = 2.0f;                            // MinLOD > MaxLOD: max(4, min(2, x)) = 4
    CHECK(calculateLod(t, s, lod2, none) == 4.0f);
    SamplerState d;
    CHECK(calculateLod(t, d, none, none) == 0.0f);      // -INF -> 0
    d.mipLodBias = 3.0f;
    CHECK(calculateLod(t, d, none, none) == 0.0f);      // -INF + 3 is still -INF
    d.mipLodBias = 0.0f;
    // §3.1 max ignores a NaN operand: max(|dX|^2 = NaN, |dY|^2 = 0) = 0 -> -INF -> 0.
    CHECK(calculateLod(t, d, {kNaN, 0}, none) == 0.0f);
    // Both NaN: LOD NaN; min(MaxLOD = FLT_MAX, NaN) = FLT_MAX -> last level 6.
    CHECK(std::isnan(calculateLodUnclamped(t, {kNaN, 0}, {kNaN, 0})));
    CHECK(calculateLod(t, d, {kNaN, 0}, {kNaN, 0}) == 6.0f);
    // sample_b adds its operand after MipLODBias (§22.4.16): 2 + 0.5 + 1.25 = 3.75 in calculateLod
    // terms; checked through the blend it produces in the trilinear test below.
}

TEST_CASE("texture: trilinear blend weight and nearest-mip selection (§7.18.10)") {
    // 2x2 float texture, R = (0, 0 / 0, 4): level 1 is the 2x2 box (0 + 0 + 0 + 4) / 4 = 1.
    const Texture2D t = Texture2D::fromFloatRgba(
        2, 2, std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 4, 0, 0, 1}, "two-by-two");
    REQUIRE(t.levels() == 2);
    CHECK(t.load({0, 0}, 1).x == 1.0f);
    // Point min/mag at uv (0.25, 0.25): level 0 texel (0, 0) = 0, level 1 texel (0, 0) = 1.
    const SamplerState trilinear = makeSampler(Filter::Point, Filter::Linear, AddressMode::Clamp);
    const glm::vec2 uv{0.25f, 0.25f};
    CHECK(sampleLevel(t, trilinear, uv, 0.25f).x == 0.25f);  // 0 + (1 - 0) * 0.25
    CHECK(sampleLevel(t, trilinear, uv, 0.75f).x == 0.75f);
    CHECK(sampleLevel(t, trilinear, uv, 1.0f).x == 1.0f);    // level 1 alone
    CHECK(sampleLevel(t, trilinear, uv, 5.0f).x == 1.0f);    // clamped to the last level
    CHECK(sampleLevel(t, trilinear, uv, -2.0f).x == 0.0f);   // magnified level 0
    // Mip Point: nearest level, a fraction of 0.5 rounds up (§7.18.10 "+0.5, integer part").
    const SamplerState nearest = makeSampler(Filter::Point, Filter::Point, AddressMode::Clamp);
    CHECK(sampleLevel(t, nearest, uv, 0.49f).x == 0.0f);
    CHECK(sampleLevel(t, nearest, uv, 0.5f).x == 1.0f);
    // From derivatives: ddx = (1/2, 0) on 2 texels -> 1 texel -> LOD 0; bias 0.25 -> 0.25.
    SamplerState biased = trilinear;
    biased.mipLodBias = 0.25f;
    CHECK(sample(t, biased, uv, {0.5f, 0}, {0, 0}).x == 0.25f);
    // sample_b: (0 + 0.25) + 0.5 = 0.75.
    CHECK(sampleBias(t, biased, uv, {0.5f, 0}, {0, 0}, 0.5f).x == 0.75f);
    // ddx = (1, 0): 2 texels -> LOD 1 -> level 1.
    CHECK(sample(t, trilinear, uv, {1.0f, 0}, {0, 0}).x == 1.0f);
    CHECK(t.sample(trilinear, uv, {1.0f, 0}, {0, 0}) == sampleGrad(t, trilinear, uv, {1.0f, 0}, {0, 0}));
    CHECK(t.calculateLevelOfDetail(biased, {0.5f, 0}, {0, 0}) == 0.25f);
}

TEST_CASE("texture: magnification when the clamped LOD <= 0, minification above (§7.18.11)") {
    const Texture2D grid = gridTexture();
    SamplerState s = makeSampler(Filter::Point, Filter::Point, AddressMode::Clamp);
    s.magFilter = Filter::Linear;  // min Point, mag Linear, mip Point
    const glm::vec2 uv{0.3125f, 0.125f};  // u * 4 = 1.25: linear s = 0.75 -> R 0.75; point texel 1
    CHECK(sampleLevel(grid, s, uv, 0.0f).x == 0.75f);    // LOD 0: magnify (linear)
    CHECK(sampleLevel(grid, s, uv, -1.0f).x == 0.75f);
    CHECK(sampleLevel(grid, s, uv, 0.25f).x == 1.0f);    // LOD 0.25: minify (point), level 0
    s.mipLodBias = 0.25f;                                 // 0 + 0.25 > 0: minify
    CHECK(sampleLevel(grid, s, uv, 0.0f).x == 1.0f);
    s.mipLodBias = 0.0f;
    s.minLod = 0.25f;                                     // max(0.25, -3) = 0.25: minify
    CHECK(sampleLevel(grid, s, uv, -3.0f).x == 1.0f);
}

TEST_CASE("texture: mip generation: 2x2 box for even sizes, 3-tap box for odd sizes (texture2d.h)") {
    // Even: R codes (0, 255 / 255, 255) -> (0 + 1 + 1 + 1) / 4 = 0.75 -> 0.75 * 255 = 191.25 -> 191;
    // G codes 10, 20, 30, 40 -> 25 (mean of k/255 is 25/255, * 255 = 25).
    const Texture2D even = Texture2D::fromImage(
        makeImage(2, 2, {0, 10, 0, 255, 255, 20, 0, 255, 255, 30, 0, 255, 255, 40, 0, 255}), TexelEncoding::Linear);
    CHECK(byteAt(even, 1, 0) == 191);
    CHECK(byteAt(even, 1, 1) == 25);
    CHECK(byteAt(even, 1, 3) == 255);

    // Odd: 5x3, R by column (255, 0, 255, 0, 0), G by row (0, 51, 255), A 255.
    std::vector<std::uint8_t> bytes;
    const std::uint8_t columnR[5] = {255, 0, 255, 0, 0};
    const std::uint8_t rowG[3] = {0, 51, 255};
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) bytes.insert(bytes.end(), {columnR[x], rowG[y], 0, 255});
    const Texture2D odd = Texture2D::fromImage(makeImage(5, 3, bytes), TexelEncoding::Linear);
    REQUIRE(odd.levels() == 3);
    // Level 1 (2x1). x = 0 reads columns 0, 1, 2 with 2/5, 2/5, 1/5: R = (2*1 + 2*0 + 1*1) / 5 =
    // 0.6 -> 153. x = 1 reads columns 2, 3, 4 with 1/5, 2/5, 2/5: R = 1/5 = 0.2 -> 51.
    // (A 2x2 box dropping column 4 would give 128 and 128.)
    CHECK(byteAt(odd, 1, 0) == 153);
    CHECK(byteAt(odd, 1, 4) == 51);
    // Rows 0, 1, 2 with 1/3 each: G = (0 + 0.2 + 1) / 3 = 0.4 -> 102 for both texels.
    CHECK(byteAt(odd, 1, 1) == 102);
    CHECK(byteAt(odd, 1, 5) == 102);
    CHECK(byteAt(odd, 1, 3) == 255);
    // Level 2 (1x1) from 2x1: R = (0.6 + 0.2) / 2 = 0.4 -> 102; G = 102.
    CHECK(byteAt(odd, 2, 0) == 102);
    CHECK(byteAt(odd, 2, 1) == 102);

    // Float 3x1 -> 1x1: (1 + 2 + 6) / 3 = 3 exactly.
    const Texture2D three = Texture2D::fromFloatRgba(3, 1, std::vector<float>{1, 0, 0, 0, 2, 0, 0, 0, 6, 0, 0, 0}, "3x1");
    CHECK(three.load({0, 0}, 1).x == 3.0f);

    // A constant texture stays exactly constant through an odd chain (each level sums
    // value * integer weights exactly and divides by their total), and any filter returns it.
    const glm::vec4 constant(0.7f, -2.5f, 1e-3f, 1.0f);
    std::vector<float> data;
    for (int i = 0; i < 7 * 5; ++i) data.insert(data.end(), {constant.x, constant.y, constant.z, constant.w});
    const Texture2D flat = Texture2D::fromFloatRgba(7, 5, data, "flat");
    REQUIRE(flat.levels() == 3);  // 7x5, 3x2, 1x1
    for (int level = 0; level < flat.levels(); ++level) CHECK(flat.load({0, 0}, level) == constant);
    const SamplerState trilinear = makeSampler(Filter::Linear, Filter::Linear, AddressMode::Wrap);
    CHECK(sampleLevel(flat, trilinear, {0.123f, -7.77f}, 0.6f) == constant);
    CHECK(sample(flat, trilinear, {0.9f, 0.45f}, {0.31f, 0.02f}, {-0.05f, 0.2f}) == constant);
}

TEST_CASE("texture: sRGB is decoded to linear before filtering and before mip averaging") {
    // 2x1 sRGB texture: codes 0 and 255 (linear 0 and 1), alpha 255 and 0.
    const Image image = makeImage(2, 1, {0, 0, 0, 255, 255, 255, 255, 0});
    const Texture2D srgb = Texture2D::fromImage(image, TexelEncoding::Srgb);
    const SamplerState linear = makeSampler(Filter::Linear, Filter::Point, AddressMode::Clamp);
    // u = 0.5: s = 2 * 0.5 - 0.5 = 0.5 -> halfway: linear 0 + (1 - 0) * 0.5 = 0.5.
    const glm::vec4 mid = sampleLevel(srgb, linear, {0.5f, 0.5f}, 0.0f);
    CHECK(mid == glm::vec4(0.5f, 0.5f, 0.5f, 0.5f));
    // Filtering the codes first would give code 127.5 ~ 128 -> sRGB decode 0.2158: not what D3D does.
    CHECK(mid.x != doctest::Approx(convert::srgb8ToLinear(128)).epsilon(0.01));

    // Mip: linear average 0.5 -> sRGB encode (§3.2.3.8): 1.055 * 0.5^(1/2.4) - 0.055 = 0.73536,
    // * 255 = 187.52 -> 188 (averaging the codes would give 128). Alpha is linear: 0.5 -> 128.
    CHECK(byteAt(srgb, 1, 0) == 188);
    CHECK(byteAt(srgb, 1, 1) == 188);
    CHECK(byteAt(srgb, 1, 2) == 188);
    CHECK(byteAt(srgb, 1, 3) == 128);
    // The same bytes as UNORM average to 0.5 -> 128.
    const Texture2D unorm = Texture2D::fromImage(image, TexelEncoding::Linear);
    CHECK(byteAt(unorm, 1, 0) == 128);

    // Load decodes too: code 128 is 0.2158605 in sRGB, 128/255 = 0.5019608 as UNORM.
    const Texture2D grey = Texture2D::fromImage(makeImage(1, 1, {128, 128, 128, 128}), TexelEncoding::Srgb);
    CHECK(grey.load({0, 0}).x == convert::srgb8ToLinear(128));
    CHECK(grey.load({0, 0}).x == doctest::Approx(0.2158605));
    CHECK(grey.load({0, 0}).w == convert::unormToFloat(128, 8));  // alpha stays linear
}

TEST_CASE("texture: Load returns 0 out of range and an empty texture behaves as unbound (§22.4.6)") {
    const Texture2D grid = gridTexture();
    CHECK(grid.load({1, 2}) == glm::vec4(1, 2, 21, 1));
    CHECK(grid.load({-1, 0}) == glm::vec4(0.0f));
    CHECK(grid.load({0, -1}) == glm::vec4(0.0f));
    CHECK(grid.load({4, 0}) == glm::vec4(0.0f));
    CHECK(grid.load({0, 4}) == glm::vec4(0.0f));
    CHECK(grid.load({0, 0}, -1) == glm::vec4(0.0f));
    CHECK(grid.load({0, 0}, 3) == glm::vec4(0.0f));   // levels 0..2 only
    CHECK(grid.load({1, 0}, 2) == glm::vec4(0.0f));   // level 2 is 1x1
    // Level 1 (2x2 box): texel (0, 0) averages (0,0), (1,0), (0,1), (1,1): R 0.5, G 0.5, B 5.5.
    CHECK(grid.load({0, 0}, 1) == glm::vec4(0.5f, 0.5f, 5.5f, 1.0f));

    const Texture2D empty;
    CHECK(empty.levels() == 0);
    CHECK(empty.width(0) == 0);
    CHECK(empty.memoryBytes() == 0);
    CHECK(empty.load({0, 0}) == glm::vec4(0.0f));
    CHECK(sample(empty, SamplerState{}, {0.5f, 0.5f}, {0.1f, 0}, {0, 0.1f}) == glm::vec4(0.0f));
    CHECK(sampleLevel(empty, SamplerState{}, {0.5f, 0.5f}, 0.0f) == glm::vec4(0.0f));
}

TEST_CASE("texture: bad images throw InputError naming their source") {
    auto fromImage = [](const Image& image) { return [image] { (void)Texture2D::fromImage(image, TexelEncoding::Srgb); }; };

    const std::string empty = thrownMessage(fromImage(makeImage(0, 0, {}, "textures/empty.png")));
    CHECK(empty.find("textures/empty.png") != std::string::npos);
    CHECK(empty.find("empty") != std::string::npos);
    CHECK(thrownMessage(fromImage(makeImage(4, 0, {}, "a.png"))).find("a.png") != std::string::npos);

    const std::string mismatch = thrownMessage(fromImage(makeImage(2, 2, std::vector<std::uint8_t>(15), "short.png")));
    CHECK(mismatch.find("short.png") != std::string::npos);
    CHECK(mismatch.find("16") != std::string::npos);  // 2 x 2 x 4 bytes expected

    const std::string wide = thrownMessage(
        fromImage(makeImage(16385, 1, std::vector<std::uint8_t>(16385 * 4), "<gltf>#/images/3")));
    CHECK(wide.find("<gltf>#/images/3") != std::string::npos);
    CHECK(wide.find("16384") != std::string::npos);
    CHECK(thrownMessage(fromImage(makeImage(1, 16385, std::vector<std::uint8_t>(16385 * 4), "tall.png")))
              .find("tall.png") != std::string::npos);

    const std::string floats = thrownMessage([] {
        (void)Texture2D::fromFloatRgba(2, 2, std::vector<float>(15), "floats.bin");
    });
    CHECK(floats.find("floats.bin") != std::string::npos);
    CHECK_THROWS_AS((void)Texture2D::fromFloatRgba(0, 1, std::vector<float>{}, "zero"), InputError);
    // The largest legal size is accepted.
    CHECK_NOTHROW((void)Texture2D::fromImage(makeImage(16384, 1, std::vector<std::uint8_t>(16384 * 4)), TexelEncoding::Linear));
}

} // namespace tessera_test::texture_texture_test

// Tables for the output merger: every depth function on D24 and D32F, every stencil op on
// both faces with read/write masks, every blend factor and op, and write masks. Expected
// values are derived in the comments from the D3D11 definitions (D3D11_COMPARISON_FUNC,
// D3D11_STENCIL_OP, D3D11_BLEND, D3D11_BLEND_OP).
#include <doctest/doctest.h>

#include <cstring>

#include <tessera/buffers/conversion.h>
#include <tessera/buffers/texel_codec.h>
#include <tessera/raster/output_merger.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::raster_output_merger_test {

using namespace tessera;

namespace {
std::array<std::byte, 8> d32Texel(float z, std::uint8_t stencil) {
    std::array<std::byte, 8> t{};
    std::memcpy(t.data(), &z, 4);
    t[4] = std::byte{stencil};
    return t;
}
std::array<std::byte, 4> d24Texel(float z, std::uint8_t stencil) {
    const std::uint32_t v = convert::depthToD24(z) | (std::uint32_t(stencil) << 24);
    std::array<std::byte, 4> t{};
    std::memcpy(t.data(), &v, 4);
    return t;
}
} // namespace

TEST_CASE("depth test: all 8 comparison functions, incoming (left) against stored (right)") {
    // Rows: func, then expected pass for incoming 0.25 / 0.5 / 0.75 against stored 0.5.
    struct Row { ComparisonFunc f; bool less, equal, greater; };
    const Row rows[] = {
        {ComparisonFunc::Never, false, false, false},     {ComparisonFunc::Less, true, false, false},
        {ComparisonFunc::Equal, false, true, false},      {ComparisonFunc::LessEqual, true, true, false},
        {ComparisonFunc::Greater, false, false, true},    {ComparisonFunc::NotEqual, true, false, true},
        {ComparisonFunc::GreaterEqual, false, true, true}, {ComparisonFunc::Always, true, true, true},
    };
    for (const Format fmt : {Format::D24_UNORM_S8_UINT, Format::D32_FLOAT_S8X24_UINT, Format::D32_FLOAT}) {
        for (const Row& r : rows) {
            DepthStencilUnit ds;
            ds.format = fmt;
            ds.desc.depthFunc = r.f;
            auto t32 = d32Texel(0.5f, 0);
            auto t24 = d24Texel(0.5f, 0);
            const std::byte* texel = fmt == Format::D24_UNORM_S8_UINT ? t24.data() : t32.data();
            const bool got[3] = {ds.test(texel, 0.25f, true) == DepthStencilResult::Pass,
                                 ds.test(texel, 0.5f, true) == DepthStencilResult::Pass,
                                 ds.test(texel, 0.75f, true) == DepthStencilResult::Pass};
            CHECK(got[0] == r.less);
            CHECK(got[1] == r.equal);
            CHECK(got[2] == r.greater);
        }
    }
}

TEST_CASE("depth test runs on the stored D24 value, not the float") {
    // 0.5 and the next float up, 0.5 + 2^-24, quantize to the same 24-bit code:
    // 0.5 * (2^24 - 1) = 8388607.5 -> 8388608 (D3D11.3 §3.2.3.6 adds 0.5 and truncates), and
    // (0.5 + 2^-24) * (2^24 - 1) = 8388608.49999994 -> 8388608 too. So EQUAL passes on D24
    // while on D32F the two values differ and EQUAL fails.
    const float zHi = 0.5f + 1.0f / 16777216.0f;
    DepthStencilUnit ds;
    ds.format = Format::D24_UNORM_S8_UINT;
    ds.desc.depthFunc = ComparisonFunc::Equal;
    auto t24 = d24Texel(0.5f, 0);
    CHECK(ds.test(t24.data(), zHi, true) == DepthStencilResult::Pass);
    ds.format = Format::D32_FLOAT_S8X24_UINT;
    auto t32 = d32Texel(0.5f, 0);
    CHECK(ds.test(t32.data(), zHi, true) == DepthStencilResult::DepthFail);
}

TEST_CASE("stencil ops on both faces, with read and write masks") {
    // stored value 0xFE (254), ref 0x0F: expected result of each op (D3D11_STENCIL_OP):
    struct Row { StencilOp op; std::uint8_t fromFE, from00, fromFF; };
    const Row rows[] = {
        {StencilOp::Keep, 0xFE, 0x00, 0xFF},    {StencilOp::Zero, 0x00, 0x00, 0x00},
        {StencilOp::Replace, 0x0F, 0x0F, 0x0F}, {StencilOp::IncrSat, 0xFF, 0x01, 0xFF},  // saturates at 255
        {StencilOp::DecrSat, 0xFD, 0x00, 0xFE}, // saturates at 0
        {StencilOp::Invert, 0x01, 0xFF, 0x00},  {StencilOp::Incr, 0xFF, 0x01, 0x00},  // 255 + 1 wraps to 0
        {StencilOp::Decr, 0xFD, 0xFF, 0xFE},    // 0 - 1 wraps to 255
    };
    for (const bool front : {true, false}) {
        for (const Row& r : rows) {
            for (const auto& [stored, want] : {std::pair{std::uint8_t(0xFE), r.fromFE}, std::pair{std::uint8_t(0x00), r.from00},
                                              std::pair{std::uint8_t(0xFF), r.fromFF}}) {
                // The op under test sits in the slot chosen by the outcome; the other face
                // carries ops that would give a different value, so a face mix-up shows.
                for (int outcome = 0; outcome < 3; ++outcome) {
                    DepthStencilUnit ds;
                    ds.format = Format::D32_FLOAT_S8X24_UINT;
                    ds.ref = 0x0F;
                    ds.desc.stencilEnable = true;
                    ds.desc.depthFunc = outcome == 1 ? ComparisonFunc::Never : ComparisonFunc::Always;
                    StencilFaceDesc tested{StencilOp::Keep, StencilOp::Keep, StencilOp::Keep,
                                           outcome == 0 ? ComparisonFunc::Never : ComparisonFunc::Always};
                    (outcome == 0 ? tested.failOp : outcome == 1 ? tested.depthFailOp : tested.passOp) = r.op;
                    StencilFaceDesc other{StencilOp::Invert, StencilOp::Invert, StencilOp::Invert, tested.func};
                    ds.desc.frontFace = front ? tested : other;
                    ds.desc.backFace = front ? other : tested;
                    auto texel = d32Texel(0.5f, stored);
                    const DepthStencilResult res = ds.test(texel.data(), 0.5f, front);
                    CHECK(int(res) == outcome);
                    ds.update(texel.data(), 0.5f, front, res);
                    CHECK(std::to_integer<int>(texel[4]) == int(want));
                }
            }
        }
    }
    SUBCASE("write mask keeps the unmasked bits; read mask applies to both operands") {
        DepthStencilUnit ds;
        ds.format = Format::D24_UNORM_S8_UINT;
        ds.ref = 0x35;
        ds.desc.stencilEnable = true;
        ds.desc.stencilWriteMask = 0x0F;
        ds.desc.depthFunc = ComparisonFunc::Always;  // isolate the stencil test
        ds.desc.frontFace = {StencilOp::Keep, StencilOp::Keep, StencilOp::Replace, ComparisonFunc::Always};
        auto t = d24Texel(0.25f, 0xA0);
        ds.update(t.data(), 0.25f, true, ds.test(t.data(), 0.25f, true));
        // (0xA0 & ~0x0F) | (0x35 & 0x0F) = 0xA0 | 0x05 = 0xA5; depth bits untouched by stencil.
        CHECK(std::to_integer<int>(t[3]) == 0xA5);
        // Read mask 0xF0: (0x35 & 0xF0) = 0x30 EQUAL (0x3C & 0xF0) = 0x30 -> pass; 0x4C -> fail.
        ds.desc.stencilReadMask = 0xF0;
        ds.desc.frontFace.func = ComparisonFunc::Equal;
        auto a = d24Texel(0.25f, 0x3C), b = d24Texel(0.25f, 0x4C);
        CHECK(ds.test(a.data(), 0.25f, true) == DepthStencilResult::Pass);
        CHECK(ds.test(b.data(), 0.25f, true) == DepthStencilResult::StencilFail);
    }
}

TEST_CASE("depth write: only on pass with the write mask on, D24 stores the rounded code") {
    DepthStencilUnit ds;
    ds.format = Format::D24_UNORM_S8_UINT;
    ds.desc.depthFunc = ComparisonFunc::Always;
    auto t = d24Texel(1.0f, 0x77);
    ds.update(t.data(), 0.1f, true, DepthStencilResult::Pass);
    std::uint32_t v;
    std::memcpy(&v, t.data(), 4);
    // 0.1f * 16777215 = 1677721.4999... (0.1f is 0.100000001490116) = 1677721.525 -> 1677722.
    CHECK((v & 0xFFFFFFu) == 1677722u);
    CHECK((v >> 24) == 0x77u);
    ds.desc.depthWriteEnable = false;
    ds.update(t.data(), 0.9f, true, DepthStencilResult::Pass);
    std::memcpy(&v, t.data(), 4);
    CHECK((v & 0xFFFFFFu) == 1677722u);
    ds.desc.depthWriteEnable = true;
    ds.update(t.data(), 0.9f, true, DepthStencilResult::DepthFail);
    std::memcpy(&v, t.data(), 4);
    CHECK((v & 0xFFFFFFu) == 1677722u);
}

TEST_CASE("blend factors and ops on R32G32B32A32_FLOAT (no quantization)") {
    // src = (0.5, 0.25, 1, 0.75), dst = (0.2, 0.4, 0.6, 0.5), blend factor k = (0.1, 0.2, 0.3, 0.4).
    const glm::vec4 s(0.5f, 0.25f, 1.0f, 0.75f), d(0.2f, 0.4f, 0.6f, 0.5f), k(0.1f, 0.2f, 0.3f, 0.4f);
    struct Row { Blend b; glm::vec4 f; };  // the factor per channel (rgb from colour rule, a from alpha rule)
    const Row rows[] = {
        {Blend::Zero, {0, 0, 0, 0}},
        {Blend::One, {1, 1, 1, 1}},
        {Blend::SrcAlpha, {0.75f, 0.75f, 0.75f, 0.75f}},
        {Blend::InvSrcAlpha, {0.25f, 0.25f, 0.25f, 0.25f}},
        {Blend::DestAlpha, {0.5f, 0.5f, 0.5f, 0.5f}},
        {Blend::InvDestAlpha, {0.5f, 0.5f, 0.5f, 0.5f}},
        {Blend::BlendFactor, k},
        {Blend::InvBlendFactor, {1 - 0.1f, 1 - 0.2f, 1 - 0.3f, 1 - 0.4f}},
        // SRC_ALPHA_SAT: f = min(As, 1 - Ad) = min(0.75, 0.5) = 0.5 for rgb, 1 for alpha.
        {Blend::SrcAlphaSat, {0.5f, 0.5f, 0.5f, 1.0f}},
    };
    auto run = [&](const RenderTargetBlendDesc& desc) {
        std::byte texel[16];
        encodeTexel(Format::R32G32B32A32_FLOAT, d, texel);
        writeColorSample(Format::R32G32B32A32_FLOAT, texel, s, desc, k);
        return decodeTexel(Format::R32G32B32A32_FLOAT, texel);
    };
    for (const Row& r : rows) {
        RenderTargetBlendDesc desc{true, r.b, Blend::Zero, BlendOp::Add, r.b, Blend::Zero, BlendOp::Add, WriteAll};
        const glm::vec4 got = run(desc);
        for (int c = 0; c < 4; ++c) CHECK(got[c] == s[c] * r.f[c]);   // src * f + dst * 0
        desc = {true, Blend::Zero, r.b, BlendOp::Add, Blend::Zero, r.b, BlendOp::Add, WriteAll};
        if (r.b == Blend::SrcAlphaSat) continue;  // D3D11 allows SRC_ALPHA_SAT as a source factor only
        const glm::vec4 got2 = run(desc);
        for (int c = 0; c < 4; ++c) CHECK(got2[c] == d[c] * r.f[c]);
    }
    // Colour factors (rgb only; alpha uses ONE): SRC_COLOR, INV_SRC_COLOR, DEST_COLOR, INV_DEST_COLOR.
    const std::pair<Blend, glm::vec3> colorRows[] = {
        {Blend::SrcColor, {0.5f, 0.25f, 1.0f}}, {Blend::InvSrcColor, {0.5f, 0.75f, 0.0f}},
        {Blend::DestColor, {0.2f, 0.4f, 0.6f}}, {Blend::InvDestColor, {1 - 0.2f, 1 - 0.4f, 1 - 0.6f}}};
    for (const auto& [b, f] : colorRows) {
        const glm::vec4 got = run({true, b, Blend::Zero, BlendOp::Add, Blend::One, Blend::Zero, BlendOp::Add, WriteAll});
        for (int c = 0; c < 3; ++c) CHECK(got[c] == s[c] * f[c]);
        CHECK(got.w == s.w);
    }
    // Ops with src factor SRC_ALPHA (0.75) and dest factor INV_SRC_ALPHA (0.25).
    const std::pair<BlendOp, glm::vec4> ops[] = {
        {BlendOp::Add, s * 0.75f + d * 0.25f},
        {BlendOp::Subtract, s * 0.75f - d * 0.25f},
        {BlendOp::RevSubtract, d * 0.25f - s * 0.75f},
        {BlendOp::Min, glm::min(s, d)},  // factors ignored
        {BlendOp::Max, glm::max(s, d)},
    };
    for (const auto& [op, want] : ops) {
        const glm::vec4 got = run({true, Blend::SrcAlpha, Blend::InvSrcAlpha, op, Blend::SrcAlpha, Blend::InvSrcAlpha, op, WriteAll});
        for (int c = 0; c < 4; ++c) CHECK(got[c] == want[c]);
    }
    // Write masks: each of the 16 masks keeps exactly the unmasked channels of dst.
    for (std::uint8_t mask = 0; mask < 16; ++mask) {
        const glm::vec4 got = run({false, Blend::One, Blend::Zero, BlendOp::Add, Blend::One, Blend::Zero, BlendOp::Add, mask});
        for (int c = 0; c < 4; ++c) CHECK(got[c] == ((mask >> c) & 1 ? s[c] : d[c]));
    }
}

TEST_CASE("UNORM targets clamp the source to [0,1] before blending and quantize the result") {
    std::byte texel[4];
    encodeTexel(Format::R8G8B8A8_UNORM, glm::vec4(0.0f, 1.0f, 0.5f, 1.0f), texel);
    // ONE + ONE with src (2, -1, 0.25, NaN): clamped src = (1, 0, 0.25, 0).
    // dst decodes to (0, 1, 128/255, 1). r = 1 + 0 -> 255; g = 0 + 1 -> 255;
    // b = 0.25 + 128/255 = 0.751 -> round(191.5...) : 0.25 + 0.50196 = 0.75196 * 255 = 191.75 -> 192;
    // a = 0 + 1 -> 255.
    writeColorSample(Format::R8G8B8A8_UNORM, texel, glm::vec4(2.0f, -1.0f, 0.25f, NAN), kAdditiveBlend, glm::vec4(1.0f));
    CHECK(std::to_integer<int>(texel[0]) == 255);
    CHECK(std::to_integer<int>(texel[1]) == 255);
    CHECK(std::to_integer<int>(texel[2]) == 192);
    CHECK(std::to_integer<int>(texel[3]) == 255);
}

TEST_CASE("UINT targets take the bit pattern and honour the write mask") {
    std::byte texel[8];
    encodeTexelUint(Format::R32G32_UINT, glm::uvec4(7, 9, 0, 0), texel);
    RenderTargetBlendDesc desc;
    desc.renderTargetWriteMask = WriteGreen;
    writeColorSample(Format::R32G32_UINT, texel, glm::uintBitsToFloat(glm::uvec4(0xDEADBEEFu, 0x12345678u, 0, 0)), desc,
                     glm::vec4(1.0f));
    const glm::uvec4 got = decodeTexelUint(Format::R32G32_UINT, texel);
    CHECK(got.x == 7u);
    CHECK(got.y == 0x12345678u);
}

} // namespace tessera_test::raster_output_merger_test

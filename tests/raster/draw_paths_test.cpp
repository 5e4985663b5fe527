// DrawStats::paths: each draw names the pipeline path the rasterizer specialised for, so that
// `tessera render --stats` shows what a frame modelled: no depth work without a depth buffer,
// no blend without blending, the sample count, exact or fast raster.
#include <doctest/doctest.h>

#include <vector>

#include <tessera/raster/device.h>

#include "support/test_draw.h"

using namespace tessera;

namespace {
DrawStats drawOne(Format depthFormat, bool blend, std::uint32_t samples, Precision precision, bool stencil = false) {
    Surface color({16, 16, Format::R8G8B8A8_UNORM, samples});
    Surface depth({16, 16, depthFormat == Format::Unknown ? Format::D32_FLOAT : depthFormat, samples});
    const std::vector<test::ColorVertex> tri{{test::windowToClip(1, 1, 16, 16)}, {test::windowToClip(15, 1, 16, 16)},
                                             {test::windowToClip(1, 15, 16, 16)}};
    DrawState st;
    st.viewport = fullViewport(color);
    st.rasterizer.cullMode = CullMode::None;
    st.precision = precision;
    if (blend) st.blend.renderTarget[0] = kAlphaBlend;
    st.depthStencil.stencilEnable = stencil;
    RenderTargets rt;
    rt.colors[0] = &color;
    if (depthFormat != Format::Unknown) rt.depthStencil = &depth;
    Device device(DeviceConfig{16, 1});
    return device.draw(st, rt, std::span<const test::ColorVertex>(tri), {}, test::PassThroughVS{}, test::ColorPS{});
}
} // namespace

TEST_CASE("draw paths: each draw reports the path its state requires") {
    CHECK(drawOne(Format::Unknown, false, 1, Precision::Exact).paths == std::map<std::string, std::uint64_t>{{"ps depth:Off 1x raster:exact", 1}});
    CHECK(drawOne(Format::D32_FLOAT, false, 1, Precision::Exact).paths.count("ps depth:D32 1x raster:exact") == 1);
    CHECK(drawOne(Format::D24_UNORM_S8_UINT, true, 1, Precision::Exact).paths.count("ps depth:D24 1x blend raster:exact") == 1);
    CHECK(drawOne(Format::D24_UNORM_S8_UINT, false, 4, Precision::Fast, true).paths.count("ps depth:General 4x raster:fast") == 1);
    DrawStats sum = drawOne(Format::D32_FLOAT, false, 1, Precision::Exact);
    sum += drawOne(Format::D32_FLOAT, false, 1, Precision::Exact);
    sum += drawOne(Format::Unknown, false, 1, Precision::Exact);
    CHECK(sum.paths["ps depth:D32 1x raster:exact"] == 2);
    CHECK(sum.paths["ps depth:Off 1x raster:exact"] == 1);
}

// The explicit instantiation of the shared pass-through draw declared `extern` in test_draw.h:
// compiled once, optimised like the library, linked into every test executable.
#include "support/test_draw.h"

template tessera::DrawStats tessera::Device::draw<tessera::test::ColorVertex, tessera::test::PassThroughVS,
                                                  tessera::test::ColorPS>(
    const DrawState&, const RenderTargets&, std::span<const tessera::test::ColorVertex>, std::span<const std::uint32_t>,
    const tessera::test::PassThroughVS&, const tessera::test::ColorPS&, OcclusionQuery*);

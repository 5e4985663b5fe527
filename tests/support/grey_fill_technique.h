// A made-up technique, "test-grey-fill", that tests register at run time to show that a technique
// declared outside the library is listed, optioned, captioned, swept and golden-tested like the
// built-in ones with no edit to src/cli or bench/ (tests/techniques/technique_registry_test.cpp,
// tests/golden/technique_golden_test.cpp).
#pragma once

#include <array>
#include <string>
#include <string_view>

#include <tessera/frame/buffer_registry.h>
#include <tessera/techniques/technique.h>

namespace tessera::test {

// Two passes: "clear" (a shared caption) creates the back buffer, "fill" (its own) writes the
// option "grey" (0, 128 or 255: a code of the UNORM target) over every pixel.
inline Frame buildGreyFill(const TechniqueContext& ctx) {
    const float grey = float(ctx.options.value("grey", 128)) / 255.0f;
    const SurfaceDesc desc{ctx.width, ctx.height, Format::R8G8B8A8_UNORM, 1};
    const std::string back(kBackBufferName);
    Frame frame;
    frame.add({"clear", {}, {back}, [desc, back](BufferRegistry& reg) { reg.create(back, desc).clearColor(glm::vec4(0.0f)); }});
    frame.add({"fill", {back}, {back}, [grey, back](BufferRegistry& reg) { reg.get(back).clearColor(glm::vec4(grey, grey, grey, 1.0f)); }});
    return frame;
}

inline constexpr std::array<std::string_view, 3> kGreyValues{"128", "0", "255"};
inline constexpr std::array<OptionInfo, 1> kGreyOptions{
    OptionInfo{"grey", OptionInfo::Kind::Integer, kGreyValues, -1, "128", "", 0, "the grey level the fill writes"}};
inline constexpr std::array<PassCaption, 1> kGreyPasses{{{"fill", "Writes one grey level over the back buffer (a test's technique)."}}};
inline const TechniqueInfo kGreyFill{"test-grey-fill", "one grey level", "tests/support/grey_fill_technique.h", &buildGreyFill,
                                     kGreyOptions, kGreyPasses, TexturePolicy::Gltf, false, 0, 0};

// Registers it once per process (doctest may run a file's cases in one process or one per case)
// and returns the registry's row.
inline const TechniqueInfo& registerGreyFill() {
    if (!findTechnique(kGreyFill.id)) registerTechnique(kGreyFill);
    return *findTechnique(kGreyFill.id);
}

} // namespace tessera::test

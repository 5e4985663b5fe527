// The `light-prepass` technique (PR&C D3D11 ch. 11 §11.3, after Engel 2009): a 32 B/px G-buffer
// (Listing 11.4), the lights summed into a light buffer (Listing 11.5), then the opaque geometry
// drawn a second time to apply the albedos (Listing 11.6). Its light passes are deferred-classic's
// (same options and light geometries, techniques/deferred_classic.h).
#pragma once

#include <array>
#include <string_view>

#include <tessera/techniques/deferred_classic.h>
#include <tessera/techniques/technique.h>

namespace tessera {

// Its options (techniques/option_catalog.h): deferred-classic's light-pass options, and msaaFinal
// (ERRATA #30); read through OptionReader, listed by `tessera options`.
namespace option_values {
inline constexpr std::array<std::string_view, 2> kMsaaFinal{"coverage", "perSample"};
} // namespace option_values

inline constexpr std::array<OptionInfo, 8> kLightPrePassOptions{
    kClassicGeometryOption, kViewVectorOption, kScissorRoundOption, kStencilMaskOption, kSamplerOption, kAlphaTestOption,
    kEdgesPrcOption,
    OptionInfo{"msaaFinal", OptionInfo::Kind::Word, option_values::kMsaaFinal, -1, "coverage", "perSample", 30,
               "MSAA second geometry pass: Listing 11.19's loop over SV_Coverage (which counts samples of surfaces in "
               "front), or per sample at edge pixels"}};

// What each pass does (TechniqueInfo::passes; "clear", "edges", "transparent", "resolve" are shared).
inline constexpr std::array<PassCaption, 3> kLightPrePassPassCaptions{{
    {"gbuffer", "Two R32G32B32A32_FLOAT targets: world normal with the specular power, world position, 32 bytes a pixel "
                "(PR&C D3D11 ch. 11 §11.3, Listing 11.4)."},
    {"lights", "Each light adds N.L x colour x attenuation and a monochrome specular to the light buffer (PR&C D3D11 "
               "ch. 11 §11.3, Listing 11.5)."},
    {"final", "The opaque geometry drawn a second time, LESS_EQUAL against its own depth: light buffer x diffuse texel "
              "+ specular x specular albedo (Listing 11.6)."},
}};

// The `light-prepass` technique (PR&C D3D11 ch. 11 §11.3, after Engel 2009): a 32 B/px G-buffer
// ("gbuffer.normal" = (world N, specular power), "gbuffer.position" = (world P, 1), Listing 11.4),
// the lights summed into "lightbuffer" R32G32B32A32_FLOAT (Listing 11.5: N.L x colour x
// attenuation in RGB, the monochrome specular without the light's colour in A), then the opaque
// geometry drawn a second time ("final", LESS_EQUAL, Listing 11.6: light.rgb x diffuse texel +
// light.a x SpecularAlbedo). The same options and light geometries as deferred-classic. The
// monochrome specular is the technique's known approximation: equal to deferred-classic's image
// (within float summation order) under white lights, different under coloured ones (tested).
Frame buildLightPrePass(const TechniqueContext& context);

} // namespace tessera

// forward-plus's "options" object (include/tessera/techniques/forward_plus.h lists the keys):
// parsed and checked into ForwardPlusOptions; a bad key or value is an InputError naming
// /options/KEY.
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include <tessera/errors/input_error.h>
#include <tessera/techniques/technique_options.h>

#include "forward_plus_detail.h"

namespace tessera::forward_plus_detail {

ForwardPlusOptions parseOptions(const TechniqueContext& ctx, const std::string& file) {
    const OptionReader r(ctx.options, kForwardPlusOptions, file);
    ForwardPlusOptions o;
    o.projection = r.is("projection", "d3d") ? ProjectionConvention::D3d : ProjectionConvention::DemoGl;
    o.sampler = r.is("sampler", "gltf") ? PhongSamplerChoice::Gltf : PhongSamplerChoice::Demo;
    o.alphaTest = r.flag("alphaTest");
    o.unbounded = r.is("lightLists", "unbounded");
    o.coneCorrected = r.is("coneTest", "corrected");
    o.brute = r.is("culling", "brute");
    o.tileSizePx = static_cast<std::uint32_t>(r.integer("tileSize"));
    return o;
}

} // namespace tessera::forward_plus_detail

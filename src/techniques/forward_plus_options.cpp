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
    ForwardPlusOptions o;
    o.projection = optionEnum(ctx.options, "projection", {"demo-gl", "d3d"}, "demo-gl", file) == "d3d"
                       ? ProjectionConvention::D3d
                       : ProjectionConvention::DemoGl;
    o.sampler = optionEnum(ctx.options, "sampler", {"demo", "gltf"}, "demo", file) == "gltf" ? PhongSamplerChoice::Gltf
                                                                                               : PhongSamplerChoice::Demo;
    o.alphaTest = optionBool(ctx.options, "alphaTest", false, file);
    o.unbounded = optionEnum(ctx.options, "lightLists", {"demo", "unbounded"}, "demo", file) == "unbounded";
    o.coneCorrected = optionEnum(ctx.options, "coneTest", {"demo", "corrected"}, "demo", file) == "corrected";
    o.brute = optionEnum(ctx.options, "culling", {"binned", "brute"}, "binned", file) == "brute";
    if (ctx.options.is_object() && ctx.options.contains("tileSize")) {
        const nlohmann::json& v = ctx.options["tileSize"];
        if (!v.is_number_integer() || (v.get<std::int64_t>() != 8 && v.get<std::int64_t>() != 16 && v.get<std::int64_t>() != 32))
            throw inputError(file, "/options/tileSize", "expected 8, 16 or 32 (tile edge in px)");
        o.tileSizePx = static_cast<std::uint32_t>(v.get<std::int64_t>());
    }
    return o;
}

} // namespace tessera::forward_plus_detail

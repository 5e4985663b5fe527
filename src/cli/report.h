// `tessera report SCENE --out DIR`: a static HTML page that walks through every technique's passes
// on one scene with the buffers each pass wrote, captions tied to the sources, one light's deferred
// stencil steps, per-pass times, and each technique's difference from `forward`.
#pragma once

#include <string_view>
#include <vector>

namespace tessera::cli {

int reportCommand(const std::vector<std::string_view>& args);

} // namespace tessera::cli

// The files of `tessera serve`'s page (src/cli/serve_page/), carried inside the binary: the
// build embeds them (cmake/embed_files.cmake), and the server answers only these names.
#pragma once

#include <string_view>
#include <vector>

namespace tessera::cli {

struct EmbeddedFile {
    std::string_view name;   // "index.html", "app.js", ...
    std::string_view bytes;
};

const std::vector<EmbeddedFile>& serveAssets();

} // namespace tessera::cli

// `tessera diff A B`: compares two images (8-bit PNG or float EXR, read through OpenImageIO) and
// reports max abs difference, RMSE and PSNR in 8-bit code units plus the count of differing
// pixels, as text or one JSON object. Exit 0 when compared (equal or not), 2 on bad input.
#pragma once

#include <string_view>
#include <vector>

namespace tessera::cli {

// Runs the subcommand on the arguments after "diff"; returns the process exit code. Throws
// tessera::InputError (exit 2) for an unreadable file or images that cannot be compared.
int diffCommand(const std::vector<std::string_view>& args);

} // namespace tessera::cli

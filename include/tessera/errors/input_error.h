// The one exception type for bad input (scene files, glTF files, images, command-line values):
// its message names the file and the key path or value at fault. The CLI maps it to exit
// code 2; every other exception while rendering maps to exit code 1.
#pragma once

#include <stdexcept>
#include <string>

namespace tessera {

struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// "FILE: KEYPATH: WHAT" (KEYPATH in JSON-pointer form, e.g. "/lights/2/range"; empty when the
// fault is the file as a whole).
inline InputError inputError(const std::string& file, const std::string& keyPath, const std::string& what) {
    return InputError(keyPath.empty() ? file + ": " + what : file + ": " + keyPath + ": " + what);
}

} // namespace tessera

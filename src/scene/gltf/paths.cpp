// JSON pointers of array elements and percent-decoded uris, for the glTF loader's messages and
// for matching the file names tinygltf reports.
#include "paths.h"

#include <cctype>
#include <cstddef>
#include <string>
#include <string_view>

namespace tessera::gltf_detail {

std::string indexPath(std::string_view base, std::size_t index) {
    return std::string(base) + "/" + std::to_string(index);
}

// A uri with its %XX escapes decoded (as tinygltf does before opening the file).
std::string percentDecoded(const std::string& uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
            out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

} // namespace tessera::gltf_detail

// Decoding of glTF accessor components and indices, and the names of component and accessor
// types for messages ("§" numbers cite the glTF 2.0 specification).
#include "accessors.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <tiny_gltf.h>

namespace tessera::gltf_detail {

const char* componentTypeName(int componentType) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return "DOUBLE";
    default: return "an unknown component type";
    }
}

const char* accessorTypeName(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "an unknown type";
    }
}

// Bytes per component (§3.6.2.2); 0 for types glTF does not allow (INT, DOUBLE).
std::size_t componentSize(int componentType) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
    }
}

std::size_t componentCount(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4:
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
    }
}

// One component as float. Normalized integers follow §3.11 ("Animations", the table of
// normalized-integer decoding, also used by KHR_mesh_quantization): signed f = max(c / (2^(b-1) - 1), -1),
// unsigned f = c / (2^b - 1). Non-normalized integers convert to their value.
float decodeComponent(const unsigned char* p, int componentType, bool normalized) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        std::int8_t c;
        std::memcpy(&c, p, 1);
        return normalized ? std::max(float(c) / 127.0f, -1.0f) : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
        std::uint8_t c;
        std::memcpy(&c, p, 1);
        return normalized ? float(c) / 255.0f : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t c;
        std::memcpy(&c, p, 2);
        return normalized ? std::max(float(c) / 32767.0f, -1.0f) : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t c;
        std::memcpy(&c, p, 2);
        return normalized ? float(c) / 65535.0f : float(c);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t c;
        std::memcpy(&c, p, 4);
        return float(c);
    }
    default: {  // FLOAT (the only other type an accessor can pass validation with)
        float c;
        std::memcpy(&c, p, 4);
        return c;
    }
    }
}

std::uint32_t decodeIndex(const unsigned char* p, int componentType) {
    if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return *p;
    if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        std::uint16_t c;
        std::memcpy(&c, p, 2);
        return c;
    }
    std::uint32_t c;
    std::memcpy(&c, p, 4);
    return c;
}

} // namespace tessera::gltf_detail

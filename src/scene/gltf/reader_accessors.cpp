// GltfReader's accessor reading (glTF 2.0 §3.6.2; "§" below cites that specification):
// bufferViews and accessor layouts checked against their buffers, sparse substitutions, the
// decode budget, and floats / indices / vertex attributes decoded from them.
#include "reader.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "paths.h"

namespace tessera::gltf_detail {

// The bytes of bufferView `index`, checked against its buffer.
const unsigned char* GltfReader::bufferViewData(int index, const std::string& referencedAt) const {
    checkIndex(index, mModel.bufferViews.size(), referencedAt, "bufferView");
    const tinygltf::BufferView& view = mModel.bufferViews[std::size_t(index)];
    const std::string path = indexPath("/bufferViews", std::size_t(index));
    checkIndex(view.buffer, mModel.buffers.size(), path + "/buffer", "buffer");
    const std::vector<unsigned char>& data = mModel.buffers[std::size_t(view.buffer)].data;
    if (view.byteLength == 0) fail(path + "/byteLength", "0 is below the minimum 1");
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
        fail(path, "byteOffset " + std::to_string(view.byteOffset) + " + byteLength " +
                       std::to_string(view.byteLength) + " exceeds buffer " + std::to_string(view.buffer) +
                       "'s " + std::to_string(data.size()) + " bytes");
    }
    return data.data() + view.byteOffset;
}

AccessorLayout GltfReader::layoutOf(int index, const std::string& referencedAt) const {
    checkIndex(index, mModel.accessors.size(), referencedAt, "accessor");
    const tinygltf::Accessor& accessor = mModel.accessors[std::size_t(index)];
    const std::string path = indexPath("/accessors", std::size_t(index));
    AccessorLayout layout;
    layout.componentType = accessor.componentType;
    layout.normalized = accessor.normalized;
    layout.count = accessor.count;
    layout.components = componentCount(accessor.type);
    layout.componentBytes = componentSize(accessor.componentType);
    if (layout.componentBytes == 0) {
        fail(path + "/componentType", std::to_string(accessor.componentType) + " (" +
                                          componentTypeName(accessor.componentType) +
                                          ") is not a glTF 2.0 component type");
    }
    if (layout.components == 0) fail(path + "/type", "unknown accessor type");
    if (accessor.count == 0) fail(path + "/count", "0 is below the minimum 1");
    if (accessor.count > MAX_ACCESSOR_ELEMENTS) {
        fail(path + "/count", std::to_string(accessor.count) + " elements exceeds the limit of 2^28");
    }
    const std::size_t elementBytes = layout.components * layout.componentBytes;
    layout.stride = elementBytes;
    if (accessor.bufferView != -1) {
        const std::string viewPath = indexPath("/bufferViews", std::size_t(std::max(accessor.bufferView, 0)));
        const unsigned char* view = bufferViewData(accessor.bufferView, path + "/bufferView");
        const tinygltf::BufferView& bufferView = mModel.bufferViews[std::size_t(accessor.bufferView)];
        if (bufferView.byteStride != 0) {
            // §3.6.2.4: byteStride is a multiple of the component size and holds one element.
            if (bufferView.byteStride < elementBytes || bufferView.byteStride % layout.componentBytes != 0) {
                fail(viewPath + "/byteStride", std::to_string(bufferView.byteStride) + " does not fit accessor " +
                                                   std::to_string(index) + "'s " + std::to_string(elementBytes) +
                                                   "-byte elements");
            }
            layout.stride = bufferView.byteStride;
        }
        const std::uint64_t needed = std::uint64_t(layout.stride) * (accessor.count - 1) + elementBytes;
        if (accessor.byteOffset > bufferView.byteLength || needed > bufferView.byteLength - accessor.byteOffset) {
            fail(path, std::to_string(accessor.count) + " elements of " + std::to_string(elementBytes) +
                           " bytes (stride " + std::to_string(layout.stride) + ") from byteOffset " +
                           std::to_string(accessor.byteOffset) + " exceed bufferView " +
                           std::to_string(accessor.bufferView) + "'s " + std::to_string(bufferView.byteLength) +
                           " bytes");
        }
        layout.first = view + accessor.byteOffset;
    } else if (!accessor.sparse.isSparse) {
        fail(path, "the accessor has neither a bufferView nor sparse values");
    }
    return layout;
}

// Applies a sparse accessor's substitutions (§3.6.2.3) by calling store(element, bytes).
template <class Store>
void GltfReader::applySparse(int index, const AccessorLayout& layout, Store&& store) const {
    const tinygltf::Accessor& accessor = mModel.accessors[std::size_t(index)];
    if (!accessor.sparse.isSparse) return;
    const std::string path = indexPath("/accessors", std::size_t(index)) + "/sparse";
    const auto& sparse = accessor.sparse;
    if (sparse.count < 1 || std::size_t(sparse.count) > accessor.count) {
        fail(path + "/count", std::to_string(sparse.count) + " is outside 1.." + std::to_string(accessor.count));
    }
    const std::size_t indexBytes = sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                                   : sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                                   : sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                                                             : 0;
    if (indexBytes == 0) fail(path + "/indices/componentType", "must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
    const std::size_t elementBytes = layout.components * layout.componentBytes;
    auto range = [&](int viewIndex, int byteOffset, std::size_t bytes, const std::string& at) {
        const unsigned char* data = bufferViewData(viewIndex, at + "/bufferView");
        const std::size_t length = mModel.bufferViews[std::size_t(viewIndex)].byteLength;
        if (byteOffset < 0 || std::size_t(byteOffset) > length || bytes > length - std::size_t(byteOffset)) {
            fail(at, std::to_string(bytes) + " bytes from byteOffset " + std::to_string(byteOffset) +
                         " exceed bufferView " + std::to_string(viewIndex) + "'s " + std::to_string(length) +
                         " bytes");
        }
        return data + byteOffset;
    };
    const std::size_t n = std::size_t(sparse.count);
    const unsigned char* indices =
        range(sparse.indices.bufferView, sparse.indices.byteOffset, n * indexBytes, path + "/indices");
    const unsigned char* values =
        range(sparse.values.bufferView, sparse.values.byteOffset, n * elementBytes, path + "/values");
    for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t element = decodeIndex(indices + k * indexBytes, sparse.indices.componentType);
        if (element >= accessor.count) {
            fail(path + "/indices", "index " + std::to_string(element) + " is not below the count " +
                                        std::to_string(accessor.count));
        }
        store(std::size_t(element), values + k * elementBytes);
    }
}

// Counts `values` 32-bit values against the file's decode budget before they are allocated.
void GltfReader::chargeDecode(std::size_t values, int index) const {
    const std::uint64_t bytes = std::uint64_t(values) * 4;
    if (bytes > mDecodeBudget - mDecoded) {
        fail(indexPath("/accessors", std::size_t(index)) + "/count",
             "decoding " + std::to_string(values) + " values would take the file's decoded accessor data past " +
                 std::to_string(mDecodeBudget >> 20) + " MiB (256 MiB + 256 bytes per buffer byte; " +
                 std::to_string(mDecoded >> 20) + " MiB decoded so far)");
    }
    mDecoded += bytes;
}

// Reads a float-decoded attribute: components floats per element.
std::vector<float> GltfReader::readFloats(int index, const std::string& referencedAt) const {
    const AccessorLayout layout = layoutOf(index, referencedAt);
    chargeDecode(layout.count * layout.components, index);
    std::vector<float> out(layout.count * layout.components, 0.0f);
    auto decodeElement = [&](std::size_t element, const unsigned char* bytes) {
        for (std::size_t c = 0; c < layout.components; ++c) {
            out[element * layout.components + c] =
                decodeComponent(bytes + c * layout.componentBytes, layout.componentType, layout.normalized);
        }
    };
    if (layout.first) {
        for (std::size_t i = 0; i < layout.count; ++i) decodeElement(i, layout.first + i * layout.stride);
    }
    applySparse(index, layout, decodeElement);
    return out;
}

std::vector<std::uint32_t> GltfReader::readIndices(int index, const std::string& referencedAt) const {
    checkIndex(index, mModel.accessors.size(), referencedAt, "accessor");
    const std::string path = indexPath("/accessors", std::size_t(index));
    const tinygltf::Accessor& accessor = mModel.accessors[std::size_t(index)];
    if (accessor.type != TINYGLTF_TYPE_SCALAR ||
        (accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
         accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
         accessor.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
        fail(path, std::string("indices must be SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, not ") +
                       accessorTypeName(accessor.type) + " of " + componentTypeName(accessor.componentType) +
                       " (used by " + referencedAt + ")");
    }
    const AccessorLayout layout = layoutOf(index, referencedAt);
    chargeDecode(layout.count, index);
    std::vector<std::uint32_t> out(layout.count, 0);
    auto decodeElement = [&](std::size_t element, const unsigned char* bytes) {
        out[element] = decodeIndex(bytes, layout.componentType);
    };
    if (layout.first) {
        for (std::size_t i = 0; i < layout.count; ++i) decodeElement(i, layout.first + i * layout.stride);
    }
    applySparse(index, layout, decodeElement);
    return out;
}

// §3.7.2.1 attribute formats, widened by KHR_mesh_quantization when the file uses it.
bool GltfReader::attributeFormatAllowed(const std::string& semantic, int type, int componentType, bool normalized) const {
    const bool isFloat = componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
    const bool isSigned8or16 =
        componentType == TINYGLTF_COMPONENT_TYPE_BYTE || componentType == TINYGLTF_COMPONENT_TYPE_SHORT;
    const bool isUnsigned8or16 = componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                 componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
    if (semantic == "POSITION") {
        return type == TINYGLTF_TYPE_VEC3 && (isFloat || (mQuantization && (isSigned8or16 || isUnsigned8or16)));
    }
    if (semantic == "NORMAL") {
        return type == TINYGLTF_TYPE_VEC3 && (isFloat || (mQuantization && isSigned8or16 && normalized));
    }
    if (semantic == "TANGENT") {
        return type == TINYGLTF_TYPE_VEC4 && (isFloat || (mQuantization && isSigned8or16 && normalized));
    }
    if (semantic == "COLOR_0") {
        return (type == TINYGLTF_TYPE_VEC3 || type == TINYGLTF_TYPE_VEC4) &&
               (isFloat || (isUnsigned8or16 && normalized) || (mQuantization && isSigned8or16 && normalized));
    }
    // TEXCOORD_n
    return type == TINYGLTF_TYPE_VEC2 &&
           (isFloat || (isUnsigned8or16 && normalized) || (mQuantization && (isSigned8or16 || isUnsigned8or16)));
}

std::vector<float> GltfReader::readAttribute(const tinygltf::Primitive& primitive, const std::string& semantic,
                                             const std::string& primitivePath, std::size_t expectedCount) const {
    const int index = primitive.attributes.at(semantic);
    const std::string referencedAt = primitivePath + "/attributes/" + semantic;
    checkIndex(index, mModel.accessors.size(), referencedAt, "accessor");
    const tinygltf::Accessor& accessor = mModel.accessors[std::size_t(index)];
    if (!attributeFormatAllowed(semantic, accessor.type, accessor.componentType, accessor.normalized)) {
        static const std::vector<std::pair<std::string, std::string>> EXPECTED = {
            {"POSITION", "VEC3 of FLOAT"}, {"NORMAL", "VEC3 of FLOAT"}, {"TANGENT", "VEC4 of FLOAT"},
            {"COLOR_0", "VEC3/VEC4 of FLOAT or normalized UNSIGNED_BYTE/UNSIGNED_SHORT"}};
        std::string expected = "VEC2 of FLOAT or normalized UNSIGNED_BYTE/UNSIGNED_SHORT";
        for (const auto& [name, format] : EXPECTED) {
            if (name == semantic) expected = format;
        }
        fail(indexPath("/accessors", std::size_t(index)),
             semantic + " must be " + expected + (mQuantization ? " (or a KHR_mesh_quantization format)" : "") +
                 ", not " + (accessor.normalized ? "normalized " : "") + accessorTypeName(accessor.type) + " of " +
                 componentTypeName(accessor.componentType) + " (used by " + referencedAt + ")");
    }
    if (expectedCount != 0 && accessor.count != expectedCount) {
        fail(referencedAt, "accessor " + std::to_string(index) + " has " + std::to_string(accessor.count) +
                               " elements but POSITION has " + std::to_string(expectedCount));
    }
    return readFloats(index, referencedAt);
}

} // namespace tessera::gltf_detail

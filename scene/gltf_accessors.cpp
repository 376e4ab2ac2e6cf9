#include "scene/gltf_accessors.h"

#include <algorithm>
#include <cstring>

#include <fmt/format.h>
#include <tiny_gltf.h>  // declarations only; libtinygltf holds the implementation

#include "core/error.h"

namespace aamap::detail {
namespace {

constexpr std::size_t kMaxElements = std::size_t{1} << 28;  // guards allocations against corrupt counts

// One element of a component type, normalised integers mapped to [0,1] / [-1,1] as in the spec.
double component(const unsigned char* p, int type, bool normalized) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); return f; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const auto v = static_cast<signed char>(p[0]);
            return normalized ? std::max(v / 127.0, -1.0) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { std::uint16_t v; std::memcpy(&v, p, 2); return normalized ? v / 65535.0 : v; }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            std::int16_t v; std::memcpy(&v, p, 2);
            return normalized ? std::max(v / 32767.0, -1.0) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { std::uint32_t v; std::memcpy(&v, p, 4); return v; }
        default: return 0.0;
    }
}

// Calls fn(element, pointer) for `count` elements of `components` values stored in bufferView `viewIndex`.
template <class Fn>
void forEachElement(const tinygltf::Model& model, int viewIndex, std::size_t byteOffset, std::size_t count,
                    int componentType, int components, const std::filesystem::path& file, const std::string& what, Fn&& fn) {
    if (viewIndex < 0 || static_cast<std::size_t>(viewIndex) >= model.bufferViews.size()) {
        throw InputError(file, fmt::format("{} uses bufferView {}, which does not exist", what, viewIndex));
    }
    const tinygltf::BufferView& view = model.bufferViews[viewIndex];
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
        throw InputError(file, fmt::format("bufferView {} uses buffer {}, which does not exist", viewIndex, view.buffer));
    }
    const auto& data = model.buffers[view.buffer].data;
    const int size = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(componentType));
    if (size <= 0) throw InputError(file, fmt::format("{} has an unknown component type {}", what, componentType));
    const std::size_t elementSize = static_cast<std::size_t>(size) * components;
    const std::size_t stride = view.byteStride ? view.byteStride : elementSize;
    const std::size_t start = view.byteOffset + byteOffset;
    if (count > 0 && (start + stride * (count - 1) + elementSize > view.byteOffset + view.byteLength ||
                      view.byteOffset + view.byteLength > data.size())) {
        throw InputError(file, fmt::format("{} reads past the end of its buffer", what));
    }
    for (std::size_t i = 0; i < count; ++i) fn(i, data.data() + start + i * stride, static_cast<std::size_t>(size));
}

const tinygltf::Accessor& accessor(const tinygltf::Model& model, int index, const std::filesystem::path& file) {
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
        throw InputError(file, fmt::format("accessor {} does not exist", index));
    }
    return model.accessors[index];
}

}  // namespace

std::vector<float> readFloats(const tinygltf::Model& model, int index, int components, const std::filesystem::path& file) {
    const tinygltf::Accessor& acc = accessor(model, index, file);
    const std::string what = fmt::format("accessor {}", index);
    if (acc.count > kMaxElements) throw InputError(file, what + " is implausibly large");
    if (tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type)) != components) {
        throw InputError(file, fmt::format("{} should have {} components per element", what, components));
    }
    std::vector<float> out(acc.count * components, 0.0f);
    const auto store = [&](std::size_t element, const unsigned char* p, std::size_t size) {
        for (int c = 0; c < components; ++c) {
            out[element * components + c] = static_cast<float>(component(p + c * size, acc.componentType, acc.normalized));
        }
    };
    if (acc.bufferView >= 0) {
        forEachElement(model, acc.bufferView, acc.byteOffset, acc.count, acc.componentType, components, file, what, store);
    }
    if (acc.sparse.isSparse) {  // replace the listed elements
        const auto& s = acc.sparse;
        std::vector<std::uint32_t> targets(s.count);
        forEachElement(model, s.indices.bufferView, s.indices.byteOffset, s.count, s.indices.componentType, 1, file,
                       what + " (sparse indices)", [&](std::size_t i, const unsigned char* p, std::size_t) {
                           targets[i] = static_cast<std::uint32_t>(component(p, s.indices.componentType, false));
                       });
        forEachElement(model, s.values.bufferView, s.values.byteOffset, s.count, acc.componentType, components, file,
                       what + " (sparse values)", [&](std::size_t i, const unsigned char* p, std::size_t size) {
                           if (targets[i] >= acc.count) throw InputError(file, what + " has a sparse index out of range");
                           store(targets[i], p, size);
                       });
    }
    return out;
}

std::vector<std::uint32_t> readIndices(const tinygltf::Model& model, int index, const std::filesystem::path& file) {
    const tinygltf::Accessor& acc = accessor(model, index, file);
    const std::string what = fmt::format("index accessor {}", index);
    if (acc.type != TINYGLTF_TYPE_SCALAR || (acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                             acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                             acc.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
        throw InputError(file, what + " must be unsigned byte, short or int scalars");
    }
    if (acc.count > kMaxElements) throw InputError(file, what + " is implausibly large");
    if (acc.bufferView < 0 || acc.sparse.isSparse) throw InputError(file, what + ": sparse or view-less indices are not supported");
    std::vector<std::uint32_t> out(acc.count);
    forEachElement(model, acc.bufferView, acc.byteOffset, acc.count, acc.componentType, 1, file, what,
                   [&](std::size_t i, const unsigned char* p, std::size_t) {
                       out[i] = static_cast<std::uint32_t>(component(p, acc.componentType, false));
                   });
    return out;
}

}  // namespace aamap::detail

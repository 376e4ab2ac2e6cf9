#pragma once
// Bounds-checked reading of glTF accessors (tinygltf model), for the glTF loader.
#include <cstdint>
#include <filesystem>
#include <vector>

namespace tinygltf {
class Model;
}

namespace aamap::detail {

// Reads accessor `index` as `components` floats per element. Accepts float data and normalised
// (u)byte/(u)short; sparse accessors are applied. Throws InputError (naming `file` and the
// accessor) on a wrong type, an out-of-range index, or a view that reads past its buffer.
std::vector<float> readFloats(const tinygltf::Model& model, int index, int components, const std::filesystem::path& file);

// Reads a SCALAR accessor of unsigned byte, short or int as indices.
std::vector<std::uint32_t> readIndices(const tinygltf::Model& model, int index, const std::filesystem::path& file);

}  // namespace aamap::detail

#pragma once
// A memory estimate for a glTF/GLB scene from its JSON alone, before tinygltf reads the buffers
// (core/memory_budget.h does the check). Counts are clamped to the bytes the file really holds,
// so a hostile declared count stays the loader's InputError rather than a memory error.
#include <cstdint>
#include <filesystem>

namespace aamap::detail {

struct GltfPrescan {
    std::uint64_t fileBytes = 0;    // the .gltf/.glb file itself (tinygltf reads it whole)
    std::uint64_t jsonBytes = 0;    // the JSON text (parsed into a DOM)
    std::uint64_t bufferBytes = 0;  // buffers, clamped to the bytes present (GLB chunk, .bin file, data URI)
    std::uint64_t vertices = 0;     // POSITION elements over all mesh instances
    std::uint64_t triangles = 0;    // index (or vertex) elements / 3 over all mesh instances
    std::uint64_t estimateBytes() const;
};

// Never throws for malformed input: what cannot be read counts as 0 and is left to the loader.
GltfPrescan prescanGltf(const std::filesystem::path& file);

// prescanGltf, then checkMemoryBudget: EnvironmentError naming the file, the estimate and the limit.
void checkGltfMemoryBudget(const std::filesystem::path& file);

}  // namespace aamap::detail

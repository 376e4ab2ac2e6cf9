// Bytes -> parseSerialized (Mitsuba's .serialized meshes), as the first and as the second mesh of
// the file: a mesh whose triangles name its own vertices, or an InputError.
#include <span>

#include "core/error.h"
#include "fuzz_input.h"
#include "scene/mitsuba_serialized.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto bytes = std::as_bytes(std::span<const std::uint8_t>(data, size));
    for (int index : {0, 1}) {
        try {
            const aamap::mitsuba::ShapeMesh m = aamap::mitsuba::parseSerialized(bytes, "fuzz.serialized", index, false);
            for (const auto& t : m.triangles)
                if (t.x >= m.positions.size() || t.y >= m.positions.size() || t.z >= m.positions.size()) std::abort();
            if (!m.normals.empty() && m.normals.size() != m.positions.size()) std::abort();
            if (!m.uvs.empty() && m.uvs.size() != m.positions.size()) std::abort();
        } catch (const aamap::InputError&) {
        }
    }
    return 0;
}

// Binary glTF (header, JSON chunk, BIN chunk) -> loadGltf.
#include "fuzz_input.h"
#include "scene/gltf_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace aamap::fuzz;
    const auto path = writeScratch("m.glb", asText(data, size));
    expectLoadOrInputError([&] { aamap::loadGltf(path); });
    return 0;
}

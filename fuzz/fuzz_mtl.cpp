// MTL text, reached through a fixed OBJ that uses its materials (and a texture beside it).
#include "fuzz_input.h"
#include "scene/obj_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace aamap::fuzz;
    static const std::filesystem::path obj = writeScratch(
        "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl a\nf 1/1 2/2 3/3\n"
                 "usemtl lamp\nf 3 2 1\n");
    writeScratch("m.mtl", asText(data, size));
    expectLoadOrInputError([&] { aamap::loadObj(obj); });
    return 0;
}

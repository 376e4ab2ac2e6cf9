// OBJ text -> loadObj, with a fixed valid MTL next to it (fuzz_mtl varies the MTL).
#include "fuzz_input.h"
#include "scene/obj_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace aamap::fuzz;
    static const bool mtl = (writeScratch("m.mtl", "newmtl a\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 4 4 4\n"), true);
    (void)mtl;
    const auto path = writeScratch("m.obj", asText(data, size));
    expectLoadOrInputError([&] { aamap::loadObj(path); });
    return 0;
}

// Radiance view files (rview/rpict options, VIEW= lines) -> parseViewText.
#include "fuzz_input.h"
#include "scene/view_file.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace aamap::fuzz;
    (void)scratchDir();  // silences logging
    expectLoadOrInputError([&] { aamap::parseViewText(asText(data, size), "m.vf"); });
    return 0;
}

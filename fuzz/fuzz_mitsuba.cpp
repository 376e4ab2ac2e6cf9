// Mitsuba scene XML -> loadMitsuba: the XML reader (includes, defaults, $parameters, refs) and the
// plugins it reaches. Mesh and map files an input names are mostly absent: an InputError.
#include "fuzz_input.h"
#include "scene/mitsuba_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace aamap::fuzz;
    const auto path = writeScratch("scene.xml", asText(data, size));
    expectLoadOrInputError([&] { aamap::loadMitsuba(path); });
    return 0;
}

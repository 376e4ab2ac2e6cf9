// Image bytes -> loadTexture (stb_image: PNG, JPEG, BMP, TGA, HDR, PNM, ... sniffed by content).
// A failure is reported through the error string, never thrown.
#include "fuzz_input.h"
#include "scene/texture_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace aamap::fuzz;
    const auto path = writeScratch("t.img", asText(data, size));
    std::string error;
    if (const auto texture = aamap::loadTexture(path, &error)) {
        if (texture->rgba.size() != static_cast<std::size_t>(texture->width) * texture->height * 4) std::abort();
    }
    return 0;
}

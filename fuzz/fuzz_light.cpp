// Light files (a YAML list, docs/lights.md) -> loadLightFile, then addLights into a scene: what the
// parser accepts, addLights must take without throwing.
#include "eval/light_list.h"
#include "fuzz_input.h"
#include "scene/light_file.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace aamap::fuzz;
    const auto path = writeScratch("lights.yaml", asText(data, size));
    expectLoadOrInputError([&] {
        const std::vector<aamap::LightSpec> lights = aamap::loadLightFile(path);
        aamap::Scene scene;
        aamap::addLights(scene, lights);
    });
    return 0;
}

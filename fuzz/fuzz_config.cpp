// Experiment YAML -> parseConfig (the scene is not loaded: the config layer alone).
#include "eval/config.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace aamap::fuzz;
    (void)scratchDir();
    expectLoadOrInputError([&] { aamap::parseConfig(std::string(asText(data, size)), "m.yaml"); });
    return 0;
}

// makeIntegrator: the one place that maps ShadingSettings::mode to an integrator class.
#include <spdlog/spdlog.h>

#include "tracer/cache_integrator.h"
#include "tracer/direct_integrator.h"
#include "tracer/integrator.h"
#include "tracer/path_integrator.h"

namespace aamap {

std::unique_ptr<Integrator> makeIntegrator(const EmbreeScene& geometry, const LightSet& lights,
                                           const ShadingSettings& shading, const IndirectDiffuseSource* indirect) {
    switch (shading.mode) {
        case ShadingMode::Path:
            return std::make_unique<PathIntegrator>(geometry, lights, shading);
        case ShadingMode::Cache:
            if (indirect != nullptr) return std::make_unique<CacheIntegrator>(geometry, lights, shading, *indirect);
            // Without a cache, Cache mode's shading is Direct's.
            if (readsIndirectDiffuse(shading))
                spdlog::warn("shading mode 'cache' without an irradiance cache: indirect diffuse light is left out");
            else
                spdlog::info("no cache: bounces {}", shading.cache.bounces);
            return std::make_unique<DirectIntegrator>(geometry, lights, shading);
        case ShadingMode::Direct:
            break;
    }
    return std::make_unique<DirectIntegrator>(geometry, lights, shading);
}

bool readsIndirectDiffuse(const ShadingSettings& shading) {
    return shading.mode == ShadingMode::Cache && shading.cache.bounces > 0;
}

}  // namespace aamap

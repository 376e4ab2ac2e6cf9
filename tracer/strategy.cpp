#include "tracer/strategy.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "tracer/block_sums.h"
#include "tracer/strategies/strategies.h"

namespace aamap {

const char* toString(StrataMapping mapping) {
    return mapping == StrataMapping::LinearRays ? "linear-rays" : "paper";
}

bool parse(const std::string& name, StrataMapping& mapping) {
    for (StrataMapping m : {StrataMapping::Paper, StrataMapping::LinearRays})
        if (name == toString(m)) {
            mapping = m;
            return true;
        }
    return false;
}

ParamSpec mappingParam() {
    return choiceParam("mapping", {toString(StrataMapping::Paper), toString(StrataMapping::LinearRays)},
                       "map value -> strata: paper (k = 1 + round(a (n-1))) or linear-rays (rays linear in a)");
}

StrataMapping mappingOf(const StrategyParams& params) {
    StrataMapping m = StrataMapping::Paper;
    parse(params.choice("mapping"), m);  // resolved: one of the schema's names
    return m;
}

int aamapStratification(float a, int n) { return stratification(a, n, StrataMapping::Paper); }

int stratification(float a, int n, StrataMapping mapping) {
    if (std::isnan(a)) return n;
    const float c = std::clamp(a, 0.0f, 1.0f);
    int k = 1;
    if (mapping == StrataMapping::Paper) {
        k = 1 + static_cast<int>(std::lround(c * static_cast<float>(n - 1)));
    } else {
        // Rays k^2 ~ 1 + a (n^2 - 1): linear in a. Double: n^2 reaches 65025.
        const double rays = 1.0 + static_cast<double>(c) * (static_cast<double>(n) * n - 1.0);
        k = static_cast<int>(std::lround(std::sqrt(rays)));
    }
    return std::clamp(k, 1, n);
}

void PerPixelStrategy::render(const SampleSource& source, const Scheduler& scheduler, StrategyImages& out) const {
    scheduler.tiles([&](int x0, int y0, int x1, int y1) {
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                const int k = stratificationFor(x, y);
                if (!out.halfDifference.empty() && k >= 2) {
                    const SampleSource::Halves h = source.pixelHalves(x, y, k);
                    out.image.at(x, y) = h.mean;
                    out.halfDifference.at(x, y) = h.difference;
                } else {
                    out.image.at(x, y) = source.pixel(x, y, k);
                }
                out.primaryRays.at(x, y) = static_cast<std::uint16_t>(k * k);
                out.traced.at(x, y) = 1;
            }
    });
}

const ParamSpec* StrategyDescriptor::param(const std::string& key) const {
    for (const ParamSpec& p : params)
        if (p.name == key) return &p;
    return nullptr;
}

namespace {

// An explicit list rather than self-registering statics: aamap_strategies is a static library,
// and the linker drops an object file nothing refers to, registrar and all. A new strategy is
// its own file in tracer/strategies/ plus one line here. A deque: registerStrategy() keeps
// earlier pointers valid.
std::deque<StrategyDescriptor>& registry() {
    static std::deque<StrategyDescriptor> all = {
        uniformStrategy(),     aamapStrategy(),    subsampleStrategy(), rpictStrategy(),
        supersampleStrategy(), varianceStrategy(), shapeIdStrategy(),   hybridStrategy(),
    };
    return all;
}

void require(bool ok, const std::string& message) {
    if (!ok) throw std::invalid_argument(message);
}

}  // namespace

const std::deque<StrategyDescriptor>& strategyRegistry() { return registry(); }

const std::string& baselineStrategyName() {
    static const std::string name = uniformStrategy().name;  // not registry().front(): tests may replace it
    return name;
}

const StrategyDescriptor* findStrategy(const std::string& name) {
    for (const StrategyDescriptor& s : registry())
        if (s.name == name) return &s;
    return nullptr;
}

std::vector<std::string> strategyNames() {
    std::vector<std::string> names;
    for (const StrategyDescriptor& s : registry()) names.push_back(s.name);
    return names;
}

void registerStrategy(StrategyDescriptor descriptor) {
    for (StrategyDescriptor& s : registry())
        if (s.name == descriptor.name) {
            s = std::move(descriptor);
            return;
        }
    registry().push_back(std::move(descriptor));
}

void unregisterStrategy(const std::string& name) {
    std::erase_if(registry(), [&](const StrategyDescriptor& s) { return s.name == name; });
}

StrategyParams resolveParams(const StrategyDescriptor& strategy, const StrategyParams& given) {
    for (const auto& [key, value] : given.entries())
        require(strategy.param(key) != nullptr,
                fmt::format("strategy '{}' has no parameter '{}'", strategy.name, key));
    StrategyParams out;
    for (const ParamSpec& p : strategy.params) {
        const ParamValue* v = given.find(p.name);
        if (v == nullptr) {
            out.set(p.name, p.defaultParam());
            continue;
        }
        std::string error;
        const std::optional<ParamValue> ok = p.check(*v, error);
        require(ok.has_value(), fmt::format("{}: {}: {}", strategy.name, p.name, error));
        out.set(p.name, *ok);
    }
    return out;
}

std::unique_ptr<SamplingStrategy> makeStrategy(const StrategySettings& s, int width, int height) {
    const StrategyDescriptor* d = findStrategy(s.name);
    require(d != nullptr, fmt::format("unknown sampling strategy '{}'", s.name));
    const int n = s.strata;
    require(n >= 1 && n <= kMaxStrata, fmt::format("strata must be in [1, {}], got {}", kMaxStrata, n));
    require(std::isfinite(s.exposure) && s.exposure > 0.0f,
            fmt::format("the display exposure must be finite and > 0, got {}", s.exposure));
    const StrategyInputs inputs{width, height, n, s.aamap, s.blockSums, s.exposure};
    if (d->usesAamap) {
        require(s.aamap != nullptr, fmt::format("{} strategy needs an aamap image", d->name));
        require(s.aamap->width() == width && s.aamap->height() == height,
                fmt::format("aamap is {}x{} but the render is {}x{}", s.aamap->width(), s.aamap->height(), width,
                            height));
    }
    if (d->needsBlockSums)
        require(s.blockSums == nullptr || (s.blockSums->width() == width && s.blockSums->height() == height),
                "block sums do not match the render size");
    std::unique_ptr<SamplingStrategy> strategy = d->create(resolveParams(*d, s.params), inputs);
    require(strategy != nullptr, fmt::format("strategy '{}' built nothing", d->name));
    require(strategy->maxRaysPerPixel() <= 65535,
            fmt::format("{}: up to {} rays per pixel do not fit the 16-bit ray map", strategy->describe(),
                        strategy->maxRaysPerPixel()));
    return strategy;
}

}  // namespace aamap

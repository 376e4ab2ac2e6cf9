#pragma once
// A SampleSource over a synthetic radiance function of the film position (in pixels), so that
// strategies can be tested without a scene. It counts every sample per pixel, independently of
// what the strategies record.
#include <atomic>
#include <functional>
#include <memory>
#include <vector>

#include <tbb/task_arena.h>

#include "tracer/sampler.h"
#include "tracer/strategy.h"

namespace aamap::testing {

class SyntheticSource final : public SampleSource {
public:
    using Radiance = std::function<glm::vec3(float fx, float fy)>;
    using Shape = std::function<std::uint32_t(float fx, float fy)>;

    // atCentre: evaluate at the pixel centre, ignoring the jitter (an exactly linear image).
    SyntheticSource(int w, int h, Radiance f, bool atCentre = false, Shape shape = {})
        : w_(w), h_(h), f_(std::move(f)), shape_(std::move(shape)), atCentre_(atCentre),
          calls_(static_cast<std::size_t>(w) * h) {}

    int width() const override { return w_; }
    int height() const override { return h_; }
    PrimarySample sample(int x, int y, int sx, int sy, int k, bool withHit) const override {
        calls_[static_cast<std::size_t>(y) * w_ + x].fetch_add(1, std::memory_order_relaxed);
        if (withHit) probes_.fetch_add(1, std::memory_order_relaxed);
        const Sampler sampler(static_cast<std::uint64_t>(y) * w_ + x, static_cast<std::uint32_t>(sy * k + sx), 7);
        const glm::vec2 j = atCentre_ ? glm::vec2(0.5f) : sampler.stratified2D(dims::kFilm, sx, sy, k);
        const float fx = static_cast<float>(x) + j.x, fy = static_cast<float>(y) + j.y;
        PrimarySample s;
        s.radiance = f_(fx, fy);
        s.finite = std::isfinite(s.radiance.x) && std::isfinite(s.radiance.y) && std::isfinite(s.radiance.z);
        if (!s.finite) s.radiance = glm::vec3(0.0f);
        if (withHit) {
            s.depth = 1.0f;
            s.shape = shape_ ? shape_(fx, fy) : 0u;
        }
        return s;
    }

    std::uint64_t calls(int x, int y) const { return calls_[static_cast<std::size_t>(y) * w_ + x].load(); }
    std::uint64_t totalCalls() const {
        std::uint64_t sum = 0;
        for (const auto& c : calls_) sum += c.load();
        return sum;
    }
    std::uint64_t probes() const { return probes_.load(); }

private:
    int w_, h_;
    Radiance f_;
    Shape shape_;
    bool atCentre_;
    mutable std::vector<std::atomic<std::uint64_t>> calls_;
    mutable std::atomic<std::uint64_t> probes_{0};
};

inline StrategyImages runStrategy(const StrategySettings& settings, const SampleSource& source, int threads = 2) {
    const auto strategy = makeStrategy(settings, source.width(), source.height());
    StrategyImages out(source.width(), source.height());
    const Scheduler scheduler(source.width(), source.height());
    tbb::task_arena arena(threads);
    arena.execute([&] { strategy->render(source, scheduler, out); });
    return out;
}

inline StrategySettings strategy(const std::string& name, int n, const ImageGrey* map = nullptr) {
    StrategySettings s;
    s.name = name;
    s.strata = n;
    s.aamap = map;
    return s;
}

// Sets `key` only where the strategy declares it: tests that configure every strategy alike.
inline void setIfDeclared(StrategySettings& s, const std::string& key, ParamValue value) {
    if (findStrategy(s.name)->param(key) != nullptr) s.params.set(key, std::move(value));
}

inline std::uint64_t sumOf(const Image<std::uint16_t>& img) {
    std::uint64_t sum = 0;
    for (auto v : img.pixels()) sum += v;
    return sum;
}

}  // namespace aamap::testing

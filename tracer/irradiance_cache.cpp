#include "tracer/irradiance_cache.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <spdlog/spdlog.h>
#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "tracer/irradiance_grid.h"
#include "tracer/irradiance_hemisphere.h"
#include "tracer/ray_offset.h"
#include "tracer/sampler.h"

namespace aamap {
namespace {

// Records decided per parallel batch: 1, 2, 4, ... up to 2^kBatchLog2. Constants, never the thread
// count: batches decide which points get records, so they must not change with the machine. The
// first batches are small because every task of a batch computes the deeper-level records its
// hemisphere needs on its own (they are merged only after the batch): starting with one record
// lets it fill the deeper levels once, which later tasks then find instead of each redoing them.
constexpr int kBatchLog2 = 6;
// Deeper levels sample fewer cells; below this the gradients are meaningless.
constexpr int kMinDivisions = 16;

// Nominal ray weight of bounce level L: 2^-L. Radiance uses the actual path weight (product of
// reflectances); the callback does not report it, so a typical reflectance of 0.5 stands in.
float levelWeight(int level) { return std::ldexp(1.0f, -level); }

// A record's random numbers follow its place in the scene, not its world coordinates: the
// position relative to the scene bounds, quantised to 2^-20 of the scene size, so a scene scaled by
// 1e-3 or 1e4 gets the same records (up to the rare point that rounds to the next step).
std::uint64_t pointSeed(const CachePoint& point, int level, std::uint64_t seed, const glm::vec3& origin,
                        float sceneSize) {
    std::uint64_t h = mix64(seed ^ 0x243f6a8885a308d3ULL);
    const glm::vec3 relative = (point.position - origin) / sceneSize;
    for (float f : {relative.x, relative.y, relative.z})
        h = mix64(h ^ static_cast<std::uint64_t>(std::llround(static_cast<double>(f) * 0x1p20)));
    for (float f : {point.normal.x, point.normal.y, point.normal.z})
        h = mix64(h ^ static_cast<std::uint64_t>(std::llround(static_cast<double>(f) * 0x1p20)));
    return mix64(h ^ static_cast<std::uint64_t>(level));
}

}  // namespace

float recordError(const IrradianceRecord& r, const glm::vec3& p, const glm::vec3& n) {
    const float d = glm::length(p - r.position);
    return d / r.radius + std::sqrt(std::max(0.0f, 1.0f - glm::dot(n, r.normal)));
}

glm::vec3 extrapolate(const IrradianceRecord& r, const glm::vec3& p, const glm::vec3& n) {
    const glm::vec3 dp = p - r.position;
    const glm::vec3 turn = glm::cross(r.normal, n);
    glm::vec3 e;
    for (int c = 0; c < 3; ++c)
        e[c] = std::max(0.0f, r.irradiance[c] + glm::dot(turn, r.gradR[c]) + glm::dot(dp, r.gradT[c]));
    return e;
}

struct IrradianceCache::Index {
    RecordGrid grid;
};

struct IrradianceCache::Local {
    explicit Local(const IrradianceCache* cache) : owner(cache), index{cache->index_->grid.emptyCopy()} {}
    const IrradianceCache* owner;
    Index index;
    std::vector<IrradianceRecord> records;
    std::uint64_t rays = 0;
};

thread_local IrradianceCache::Local* IrradianceCache::current_ = nullptr;

IrradianceCache::IrradianceCache(const IrradianceCacheSettings& settings, const Bounds& sceneBounds,
                                 RadianceFn radiance)
    : settings_(settings), radiance_(std::move(radiance)) {
    if (settings_.bounces < 0 || settings_.divisions < 1 || settings_.supersamples < 0 || settings_.resolution < 0 ||
        !(settings_.accuracy > 0.0f) || settings_.threads < 0)
        throw std::invalid_argument(fmt::format("irradiance cache: bad settings -ab {} -ad {} -as {} -aa {} -ar {}",
                                                settings_.bounces, settings_.divisions, settings_.supersamples,
                                                settings_.accuracy, settings_.resolution));
    const glm::vec3 ext = sceneBounds.extent();
    sceneSize_ = std::max({ext.x, ext.y, ext.z, 1e-6f});
    // Radiance's setambres(): min radius = size / ar, max = 64 min (at most half the scene).
    if (settings_.resolution > 0) {
        minRadius_ = sceneSize_ / static_cast<float>(settings_.resolution);
        maxRadius_ = std::min(64.0f * minRadius_, 0.5f * sceneSize_);
    } else {
        minRadius_ = 1e-4f * sceneSize_;
        maxRadius_ = 0.5f * sceneSize_;
    }
    if (maxRadius_ <= minRadius_) maxRadius_ = 64.0f * minRadius_;
    behindTolerance_ = settings_.accuracy * minRadius_ + 1e-4f * sceneSize_;
    origin_ = sceneBounds.lo;
    // Stands in for the triangle's vertex scale in rayOffset (the cache only sees points).
    offsetScale_ = std::max({std::abs(sceneBounds.lo.x), std::abs(sceneBounds.lo.y), std::abs(sceneBounds.lo.z),
                             std::abs(sceneBounds.hi.x), std::abs(sceneBounds.hi.y), std::abs(sceneBounds.hi.z),
                             sceneSize_});
    index_ = std::make_unique<Index>();
    const float reach = settings_.accuracy * maxRadius_;
    index_->grid = RecordGrid(origin_, std::max(2.0f * settings_.accuracy * minRadius_, reach * 0x1p-14f), reach);
    stats_.recordsPerLevel.assign(static_cast<std::size_t>(std::max(1, settings_.bounces)), 0);
}

IrradianceCache::~IrradianceCache() = default;

void IrradianceCache::insertInto(Index& index, std::vector<IrradianceRecord>& records,
                                 const IrradianceRecord& r) const {
    index.grid.insert(static_cast<std::uint32_t>(records.size()), r.position, settings_.accuracy * r.radius);
    records.push_back(r);
}

void IrradianceCache::insert(const IrradianceRecord& record) {
    if (!(record.radius > 0.0f)) throw std::invalid_argument("irradiance record radius must be > 0");
    insertInto(*index_, records_, record);
}

bool IrradianceCache::lookup(const Index& index, std::span<const IrradianceRecord> records, const glm::vec3& p,
                             const glm::vec3& n, int level, glm::vec3& sum, float& wsum) const {
    const float a = settings_.accuracy;
    bool any = false;
    index.grid.forEachNear(p, [&](std::uint32_t id) {
        const IrradianceRecord& r = records[id];
        // A record holds the light of its own level's remaining bounces (level L: bounces - L), so
        // it is used at that level only. A shallower record would add the bounces the path at
        // this level no longer has: Radiance's "lvl <= current" test lets it, which biases a
        // B-bounce cache above the B-bounce path-traced answer.
        if (r.level != level) return;
        const float e = recordError(r, p, n);
        if (!(e < a)) return;  // Ward: w = 1/e > 1/a
        // "Behind" test: a record in front of p (p below its tangent plane, averaged with ours)
        // sees light that p may not, e.g. across an inside corner.
        if (0.5f * glm::dot(p - r.position, r.normal + n) < -behindTolerance_) return;
        const float w = e > 1e-3f ? 1.0f / e : 1e3f;
        sum += w * extrapolate(r, p, n);
        wsum += w;
        any = true;
    });
    return any;
}

bool IrradianceCache::interpolate(const glm::vec3& p, const glm::vec3& n, int level, glm::vec3& out) const {
    glm::vec3 sum(0.0f);
    float wsum = 0.0f;
    lookup(*index_, records_, p, n, level, sum, wsum);
    if (current_ != nullptr && current_->owner == this)
        lookup(current_->index, current_->records, p, n, level, sum, wsum);
    if (!(wsum > 0.0f)) return false;
    out = sum / wsum;
    return true;
}

bool IrradianceCache::covered(const glm::vec3& p, const glm::vec3& n, int level) const {
    glm::vec3 sum(0.0f);
    float wsum = 0.0f;
    return lookup(*index_, records_, p, n, level, sum, wsum);
}

glm::vec3 IrradianceCache::irradiance(const glm::vec3& p, const glm::vec3& n, int level) const {
    if (level < 0 || level >= settings_.bounces) return glm::vec3(0.0f);
    glm::vec3 e;
    if (interpolate(p, n, level, e)) return e;
    // A miss. Inside the pre-pass (current_ set) the new record joins the task's Local and is
    // merged after the batch. After build() it is computed on the fly and dropped: storing it
    // would make later pixels depend on which thread got there first. In probe mode only the
    // point is kept, for the next build().
    Local* local = current_ != nullptr && current_->owner == this ? current_ : nullptr;
    const bool outermost = local == nullptr;
    if (outermost && probe_) {
        probeMisses_.local().push_back({p, n});
        return glm::vec3(0.0f);
    }
    Local scratch(this);
    Local* const previous = current_;
    if (outermost) {
        local = &scratch;
        current_ = &scratch;  // deeper misses of this estimate reuse each other's records
        renderMisses_.fetch_add(1, std::memory_order_relaxed);
    }
    const IrradianceRecord r = computeRecordCounted({p, n}, level, local->rays);
    insertInto(local->index, local->records, r);
    if (outermost) {
        current_ = previous;
        renderRays_.fetch_add(scratch.rays, std::memory_order_relaxed);
    }
    return r.irradiance;
}

std::vector<CachePoint> IrradianceCache::takeMisses() {
    std::vector<CachePoint> all;
    for (std::vector<CachePoint>& v : probeMisses_) {
        all.insert(all.end(), v.begin(), v.end());
        v.clear();
    }
    // Sorted by a hash of each point's bits: a fixed order, and one that spreads consecutive
    // points over the image as the coarse-to-fine candidates do (neighbours in a batch would end
    // it early, see build()).
    const auto bits = [](const CachePoint& c) {
        return std::array<std::uint32_t, 6>{std::bit_cast<std::uint32_t>(c.position.x), std::bit_cast<std::uint32_t>(c.position.y),
                                            std::bit_cast<std::uint32_t>(c.position.z), std::bit_cast<std::uint32_t>(c.normal.x),
                                            std::bit_cast<std::uint32_t>(c.normal.y), std::bit_cast<std::uint32_t>(c.normal.z)};
    };
    const auto hash = [&](const CachePoint& c) {
        std::uint64_t h = 0x9e3779b97f4a7c15ULL;
        for (std::uint32_t b : bits(c)) h = mix64(h ^ b);
        return h;
    };
    std::sort(all.begin(), all.end(), [&](const CachePoint& a, const CachePoint& b) {
        const std::uint64_t ha = hash(a), hb = hash(b);
        return ha != hb ? ha < hb : bits(a) < bits(b);
    });
    all.erase(std::unique(all.begin(), all.end(), [&](const CachePoint& a, const CachePoint& b) { return bits(a) == bits(b); }),
              all.end());
    return all;
}

IrradianceRecord IrradianceCache::computeRecord(const CachePoint& point, int level) const {
    // Like a miss: deeper misses inside this estimate share a scratch Local, then it is dropped.
    Local scratch(this);
    Local* const previous = current_;
    current_ = &scratch;
    const IrradianceRecord r = computeRecordCounted(point, level, scratch.rays);
    current_ = previous;
    return r;
}

IrradianceRecord IrradianceCache::computeRecordCounted(const CachePoint& point, int level,
                                                       std::uint64_t& rays) const {
    const float weight = levelWeight(level);
    const int divisions =
        std::max(kMinDivisions, static_cast<int>(std::lround(static_cast<float>(settings_.divisions) * weight)));
    const int supersamples = static_cast<int>(std::lround(static_cast<float>(settings_.supersamples) * weight));
    const HemisphereEstimate est = sampleHemisphere(point.position, point.normal, rayOffset(point.position, offsetScale_),
                                                    divisions, supersamples, level + 1,
                                                    pointSeed(point, level, settings_.seed, origin_, sceneSize_), radiance_);
    rays += est.rays;

    IrradianceRecord r;
    r.position = point.position;
    r.normal = point.normal;
    r.irradiance = est.irradiance;
    r.level = level;
    r.gradT = est.gradT;
    r.gradR = est.gradR;
    // Radius as in Radiance's doambient(): the harmonic-mean distance, shrunk where the
    // translational gradient would change E by more than E over it; at least the -ar minimum (the
    // gradient is then capped instead); grown by 1/sqrt(weight) at deeper levels; at most maxR.
    float radius = std::isfinite(est.harmonicDistance) ? est.harmonicDistance : maxRadius_;
    const float b = brightness(r.irradiance);
    const glm::vec3 gb = 0.2651f * r.gradT[0] + 0.6701f * r.gradT[1] + 0.0648f * r.gradT[2];
    const float g = glm::length(gb);
    if (b > 0.0f && g * radius > b) radius = b / g;
    if (radius < minRadius_) {
        radius = minRadius_;
        if (b > 0.0f && g * radius > b)
            for (glm::vec3& v : r.gradT) v *= b / (g * radius);
    }
    if (!(b > 0.0f))
        for (glm::vec3& v : r.gradT) v = glm::vec3(0.0f);
    r.radius = std::min(radius / std::sqrt(weight), maxRadius_);
    return r;
}

void IrradianceCache::build(std::span<const CachePoint> points) {
    if (!enabled()) return;
    const auto start = std::chrono::steady_clock::now();
    stats_.candidates += points.size();
    const float a = settings_.accuracy;
    const int threads = settings_.threads > 0 ? settings_.threads : tbb::info::default_concurrency();
    tbb::task_arena arena(threads);

    std::vector<CachePoint> batch;
    std::vector<IrradianceRecord> results;
    std::vector<Local> locals;
    std::vector<float> radii;
    std::size_t pos = 0;
    while (pos < points.size()) {
        // Provisional spacing inside a batch: half the median level-0 radius so far. A point too
        // close to one already in the batch ends the batch and is looked at again afterwards,
        // against real records.
        radii.clear();
        for (const IrradianceRecord& r : records_)
            if (r.level == 0) radii.push_back(r.radius);
        float guess = minRadius_;
        if (radii.size() >= 16) {
            std::nth_element(radii.begin(), radii.begin() + static_cast<std::ptrdiff_t>(radii.size() / 2), radii.end());
            guess = std::max(guess, 0.5f * radii[radii.size() / 2]);
        }
        batch.clear();
        const std::size_t capacity = std::size_t{1} << std::min<std::size_t>(stats_.batches, kBatchLog2);
        while (batch.size() < capacity && pos < points.size()) {
            const CachePoint& c = points[pos];
            if (covered(c.position, c.normal, 0)) {
                ++pos;
                continue;
            }
            const bool crowded = std::any_of(batch.begin(), batch.end(), [&](const CachePoint& q) {
                IrradianceRecord probe;
                probe.position = q.position;
                probe.normal = q.normal;
                probe.radius = guess;
                return recordError(probe, c.position, c.normal) < a;
            });
            if (crowded) break;
            batch.push_back(c);
            ++pos;
        }
        if (batch.empty()) continue;

        // The expensive part: each record's hemisphere sees the cache as it was before the batch
        // plus the records its own task made, so it does not depend on scheduling.
        results.assign(batch.size(), IrradianceRecord{});
        locals.clear();
        locals.reserve(batch.size());
        for (std::size_t i = 0; i < batch.size(); ++i) locals.emplace_back(this);
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<std::size_t>(0, batch.size(), 1),
                              [&](const tbb::blocked_range<std::size_t>& range) {
                                  for (std::size_t i = range.begin(); i != range.end(); ++i) {
                                      Local& local = locals[i];
                                      Local* const previous = current_;
                                      current_ = &local;
                                      results[i] = computeRecordCounted(batch[i], 0, local.rays);
                                      current_ = previous;
                                  }
                              });
        });
        // Merge in batch order: the batch's records, then each task's deeper records unless an
        // earlier one covers them already.
        for (const IrradianceRecord& r : results) insertInto(*index_, records_, r);
        for (const Local& local : locals) {
            stats_.buildRays += local.rays;
            for (const IrradianceRecord& r : local.records)
                if (!covered(r.position, r.normal, r.level)) insertInto(*index_, records_, r);
        }
        ++stats_.batches;
    }
    stats_.buildSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const IrradianceCacheStats s = stats();
    spdlog::debug("irradiance cache: {} records from {} points in {} batches, {:.3f} s, {} rays", s.records,
                  s.candidates, s.batches, s.buildSeconds, s.buildRays);
}

IrradianceCacheStats IrradianceCache::stats() const {
    IrradianceCacheStats s = stats_;
    s.records = records_.size();
    for (const IrradianceRecord& r : records_) {
        const auto level = static_cast<std::size_t>(std::max(0, r.level));
        if (level >= s.recordsPerLevel.size()) s.recordsPerLevel.resize(level + 1, 0);
        ++s.recordsPerLevel[level];
    }
    s.renderMisses = renderMisses_.load(std::memory_order_relaxed);
    s.renderRays = renderRays_.load(std::memory_order_relaxed);
    return s;
}

}  // namespace aamap

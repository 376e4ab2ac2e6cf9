#pragma once
// Irradiance cache for indirect diffuse light: Ward, Rubinstein & Clear 1988 with the gradients of
// Ward & Heckbert 1992, as in Radiance (-ab, -ad, -as, -aa, -ar). Built in a deterministic pre-pass,
// then read-only while the image renders, so the image does not depend on the thread count.
// Formulas, parameters and the differences from Radiance: docs/irradiance-cache.md.
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <tbb/enumerable_thread_specific.h>

#include "scene/lights.h"

namespace aamap {

class EmbreeScene;
struct PinholeCamera;

struct IrradianceCacheSettings {
    int bounces = 1;          // -ab: diffuse bounces; 0 disables the cache (irradiance() returns 0)
    int divisions = 512;      // -ad: hemisphere samples of a level-0 record (M x N cells)
    int supersamples = 128;   // -as: extra samples spent on the cells with the largest differences
    float accuracy = 0.2f;    // -aa: a record is used where its error 1/w is below this
    int resolution = 64;      // -ar: minimum record radius = scene size / ar (0: no minimum)
    // The pre-pass takes the first hits of one camera ray per gridStep x gridStep pixels (at
    // least a 32 x 32 grid, or the image size if smaller). docs/irradiance-cache.md, "Wiring".
    int gridStep = 4;
    std::uint64_t seed = 1;   // decorrelates caches; records are a pure function of it
    int threads = 0;          // pre-pass threads, 0 = all; the cache does not depend on it
    bool operator==(const IrradianceCacheSettings&) const = default;
};

// What the integrator returns for one hemisphere ray.
struct RadianceSample {
    glm::vec3 radiance{0.0f};                                 // radiance arriving along -dir
    float distance = std::numeric_limits<float>::infinity();  // to the hit; infinity on a miss
};

// Radiance arriving at `origin` from direction `dir` (unit; the ray leaves origin along dir).
// `depth` >= 1 is the bounce of the hit: for depth < bounces the callback adds, at a diffuse hit q
// with normal nq, kd/pi * cache.irradiance(q, nq, depth). `seed` seeds its own light samples. Must be
// thread-safe and a pure function of its arguments (and of the frozen cache).
using RadianceFn =
    std::function<RadianceSample(const glm::vec3& origin, const glm::vec3& dir, int depth, std::uint64_t seed)>;

struct CachePoint {
    glm::vec3 position;
    glm::vec3 normal;  // unit, on the side the light is gathered from
};

struct IrradianceRecord {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    glm::vec3 irradiance{0.0f};  // E (RGB), W/m^2 in scene units
    float radius = 1.0f;         // R_i: clamped harmonic-mean distance to the surfaces seen
    int level = 0;               // bounce level it was computed for; used at that level only
    std::array<glm::vec3, 3> gradT{};  // dE_c/dp for c = r, g, b (Ward & Heckbert translational)
    std::array<glm::vec3, 3> gradR{};  // rotational: E_c(n) ~ E_c + dot(cross(n_i, n), gradR[c])
    bool operator==(const IrradianceRecord&) const = default;
};

// Ward's error 1/w_i = |p - p_i| / R_i + sqrt(1 - n.n_i); w_i is the interpolation weight.
float recordError(const IrradianceRecord& r, const glm::vec3& p, const glm::vec3& n);
// The record's estimate at (p, n), extrapolated with both gradients, clamped to >= 0.
glm::vec3 extrapolate(const IrradianceRecord& r, const glm::vec3& p, const glm::vec3& n);

struct IrradianceCacheStats {
    std::size_t records = 0;
    std::vector<std::size_t> recordsPerLevel;  // index = level
    std::size_t candidates = 0;      // points offered to build()
    std::size_t batches = 0;         // parallel batches in the pre-pass
    double buildSeconds = 0.0;
    std::uint64_t buildRays = 0;     // RadianceFn calls made by the pre-pass
    std::uint64_t renderMisses = 0;  // lookups after build() that no record covered
    std::uint64_t renderRays = 0;    // RadianceFn calls those misses made
};

class IrradianceCache {
public:
    // `sceneBounds` sets the scale of -ar (scene size = largest extent). `radiance` must outlive
    // the cache and may call back into it (irradiance() at depth >= 1).
    IrradianceCache(const IrradianceCacheSettings& settings, const Bounds& sceneBounds, RadianceFn radiance);
    ~IrradianceCache();
    IrradianceCache(const IrradianceCache&) = delete;
    IrradianceCache& operator=(const IrradianceCache&) = delete;

    bool enabled() const { return settings_.bounces > 0; }
    const IrradianceCacheSettings& settings() const { return settings_; }
    float minRadius() const { return minRadius_; }
    float maxRadius() const { return maxRadius_; }

    // The pre-pass: visits the points in order and adds a record where none covers the point;
    // records of a batch are computed in parallel and inserted in order. Deterministic for any
    // thread count. Records for deeper bounces (hidden surfaces) are added on the way. Call once,
    // before any concurrent irradiance(). Does nothing when bounces == 0.
    void build(std::span<const CachePoint> points);

    // Irradiance at (p, n) for bounce `level` (0: the first diffuse hit of a camera path); zero
    // when level >= bounces. Interpolates the records; where none covers p it computes a
    // deterministic estimate that is NOT stored (counted in stats().renderMisses). Thread-safe.
    glm::vec3 irradiance(const glm::vec3& p, const glm::vec3& n, int level = 0) const;

    // Probe mode (after build()): a level-0 lookup that no record covers is not computed; its
    // point is kept for takeMisses() and the lookup returns 0. A render in probe mode finds the
    // points its samples need; building records for them first leaves the real render no misses
    // (each miss computes a record that is then dropped, so misses are the render's main cost).
    void setProbe(bool on) { probe_ = on; }
    // The points probe mode kept, in an order fixed by their values (not by threads or timing),
    // duplicates removed; clears them.
    std::vector<CachePoint> takeMisses();

    // Interpolation only: false (out untouched) when no record covers (p, n) at `level`.
    bool interpolate(const glm::vec3& p, const glm::vec3& n, int level, glm::vec3& out) const;

    // Adds a finished record directly (tests, tools). Not thread-safe.
    void insert(const IrradianceRecord& record);
    // Computes (does not store) the record at a point: the hemisphere pre-pass of one record.
    IrradianceRecord computeRecord(const CachePoint& point, int level) const;

    std::span<const IrradianceRecord> records() const { return records_; }
    IrradianceCacheStats stats() const;

private:
    struct Index;
    struct Local;  // records made while computing one record (deeper levels), private to a task

    bool lookup(const Index& index, std::span<const IrradianceRecord> records, const glm::vec3& p,
                const glm::vec3& n, int level, glm::vec3& sum, float& wsum) const;
    bool covered(const glm::vec3& p, const glm::vec3& n, int level) const;
    IrradianceRecord computeRecordCounted(const CachePoint& point, int level, std::uint64_t& rays) const;
    void insertInto(Index& index, std::vector<IrradianceRecord>& records, const IrradianceRecord& r) const;

    IrradianceCacheSettings settings_;
    RadianceFn radiance_;
    float sceneSize_ = 1.0f;
    float minRadius_ = 0.0f, maxRadius_ = 1.0f;
    glm::vec3 origin_{0.0f};  // grid origin (scene bounds minimum)
    float offsetScale_ = 1.0f;
    std::vector<IrradianceRecord> records_;
    std::unique_ptr<Index> index_;
    IrradianceCacheStats stats_;
    float behindTolerance_ = 0.0f;
    mutable std::atomic<std::uint64_t> renderMisses_{0}, renderRays_{0};
    bool probe_ = false;
    mutable tbb::enumerable_thread_specific<std::vector<CachePoint>> probeMisses_;
    static thread_local Local* current_;  // the task's Local while a record is being computed
};

// Candidate points for build(): the first hits (emitters excluded) of camera rays through the
// centres of a gridW x gridH film grid, ordered coarse to fine (every 2^k-th point before the
// points between them), so early batches spread over the image and later points are mostly
// covered already.
std::vector<CachePoint> cameraCachePoints(const EmbreeScene& geometry, const PinholeCamera& camera, int gridW,
                                          int gridH);

}  // namespace aamap

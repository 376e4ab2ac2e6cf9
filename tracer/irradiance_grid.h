#pragma once
// Spatial index of the cache records: a hierarchy of hashed uniform grids (an octree without the
// tree). A record whose coverage sphere has radius r lives in the finest level whose cell size
// s >= 2r, in the cell holding its centre; a record covering p then has its centre within s/2 of
// p, i.e. in one of at most 2 x 2 x 2 cells around p per level. Visit order is fixed (level, cell,
// insertion), so sums over the visited records are reproducible.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

namespace aamap {

class RecordGrid {
public:
    static constexpr int kMaxLevels = 15;

    RecordGrid() = default;
    // `finest`: cell size of level 0; `largest`: the largest coverage radius expected (bigger
    // ones go to a list that every query visits).
    RecordGrid(const glm::vec3& origin, float finest, float largest) : origin_(origin), finest_(finest) {
        levels_ = 1;
        while (levels_ < kMaxLevels && cellSize(levels_ - 1) < 2.0f * largest) ++levels_;
    }

    // Same geometry, no records.
    RecordGrid emptyCopy() const {
        RecordGrid g;
        g.origin_ = origin_;
        g.finest_ = finest_;
        g.levels_ = levels_;
        return g;
    }

    void insert(std::uint32_t id, const glm::vec3& centre, float reach) {
        int level = 0;
        while (level < levels_ && cellSize(level) < 2.0f * reach) ++level;
        if (level == levels_) {
            big_.push_back(id);
            return;
        }
        usedLevels_ |= 1u << level;
        const float s = cellSize(level);
        const glm::vec3 q = (centre - origin_) / s;
        cells_[key(level, cellOf(q.x), cellOf(q.y), cellOf(q.z))].push_back(id);
    }

    // Calls f(id) for every record that may cover p (and some that do not).
    template <class F>
    void forEachNear(const glm::vec3& p, F&& f) const {
        for (int level = 0; level < levels_; ++level) {
            if (!(usedLevels_ & (1u << level))) continue;
            const float s = cellSize(level);
            const glm::vec3 q = (p - origin_) / s;
            const int x0 = cellOf(q.x - 0.5f), x1 = cellOf(q.x + 0.5f);
            const int y0 = cellOf(q.y - 0.5f), y1 = cellOf(q.y + 0.5f);
            const int z0 = cellOf(q.z - 0.5f), z1 = cellOf(q.z + 0.5f);
            for (int x = x0; x <= x1; ++x)
                for (int y = y0; y <= y1; ++y)
                    for (int z = z0; z <= z1; ++z) {
                        const auto it = cells_.find(key(level, x, y, z));
                        if (it == cells_.end()) continue;
                        for (std::uint32_t id : it->second) f(id);
                    }
        }
        for (std::uint32_t id : big_) f(id);
    }

private:
    static constexpr int kBias = 1 << 19;  // 20 bits per axis

    float cellSize(int level) const { return std::ldexp(finest_, level); }
    // Clamped (monotonic, so a clamped query range still holds the clamped record cell).
    static int cellOf(float v) {
        const float f = std::floor(v);
        if (!(f > -static_cast<float>(kBias))) return -kBias;
        if (f >= static_cast<float>(kBias - 1)) return kBias - 1;
        return static_cast<int>(f);
    }
    static std::uint64_t key(int level, int x, int y, int z) {
        return (static_cast<std::uint64_t>(level) << 60) | (static_cast<std::uint64_t>(x + kBias) << 40) |
               (static_cast<std::uint64_t>(y + kBias) << 20) | static_cast<std::uint64_t>(z + kBias);
    }

    glm::vec3 origin_{0.0f};
    float finest_ = 1.0f;
    int levels_ = 1;
    std::uint32_t usedLevels_ = 0;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
    std::vector<std::uint32_t> big_;
};

}  // namespace aamap

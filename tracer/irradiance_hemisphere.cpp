#include "tracer/irradiance_hemisphere.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "tracer/sampler.h"

namespace aamap {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Orthonormal basis around a unit normal (Duff et al. 2017): continuous except at n.z = -1 flips,
// and a pure function of n, which is all determinism needs.
void basis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
    const float s = std::copysign(1.0f, n.z);
    const float a = -1.0f / (s + n.z);
    const float c = n.x * n.y * a;
    t = glm::vec3(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    b = glm::vec3(c, s + n.y * n.y * a, -n.y);
}

struct Cell {
    glm::dvec3 sum{0.0};   // radiance summed over the samples taken
    double invDist = 0.0;  // sum of 1 / distance (misses add 0)
    int count = 0;
    glm::dvec3 mean() const { return count > 0 ? sum / static_cast<double>(count) : glm::dvec3(0.0); }
    double meanInvDist() const { return count > 0 ? invDist / count : 0.0; }
};

bool finite(const glm::vec3& c) { return std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z); }

// Mean of tan(theta) over theta row j of M under the cosine-weighted measure (u = sin^2 theta
// uniform): M * [F(u)] from j/M to (j+1)/M with F(u) = asin(sqrt(u)) - sqrt(u (1 - u)). Radiance
// takes tan at the row centre, which is ~10% low (tan is convex and the top row is unbounded);
// each sample's own tan (W&H) is unbiased but noisy. This is exact for a cell-constant L, noiseless.
double meanTan(int j, int M) {
    auto F = [](double u) { return std::asin(std::sqrt(u)) - std::sqrt(u * (1.0 - u)); };
    return M * (F(static_cast<double>(j + 1) / M) - F(static_cast<double>(j) / M));
}

double bright(const glm::dvec3& c) { return 0.2651 * c.x + 0.6701 * c.y + 0.0648 * c.z; }

}  // namespace

HemisphereLayout hemisphereLayout(int divisions) {
    const double d = std::max(1, divisions);
    const int m = std::max(1, static_cast<int>(std::lround(std::sqrt(d / kPi))));
    const int n = std::max(1, static_cast<int>(std::lround(kPi * m)));
    return {m, n};
}

HemisphereEstimate sampleHemisphere(const glm::vec3& p, const glm::vec3& n, float offset, int divisions,
                                    int supersamples, int depth, std::uint64_t seed, const RadianceFn& radiance) {
    const HemisphereLayout layout = hemisphereLayout(divisions);
    const int M = layout.theta, N = layout.phi;
    glm::vec3 t, b;
    basis(n, t, b);
    const glm::vec3 origin = p + offset * n;
    std::vector<Cell> cells(static_cast<std::size_t>(M) * N);
    HemisphereEstimate est;

    auto sampleCell = [&](int j, int k) {
        Cell& c = cells[static_cast<std::size_t>(j) * N + k];
        const std::uint64_t cell = static_cast<std::uint64_t>(j) * N + k;
        const std::uint64_t key = mix64(seed + mix64((cell << 32) | static_cast<std::uint32_t>(c.count)));
        const float xi1 = static_cast<float>(key >> 40) * 0x1p-24f;
        const float xi2 = static_cast<float>((key >> 16) & 0xffffffu) * 0x1p-24f;
        // Cosine-weighted: sin^2(theta) uniform in the cell's [j/M, (j+1)/M).
        const double u = (j + static_cast<double>(xi1)) / M;
        const double sinT = std::sqrt(u), cosT = std::sqrt(std::max(0.0, 1.0 - u));
        const double phi = 2.0 * kPi * (k + static_cast<double>(xi2)) / N;
        const glm::vec3 dir = glm::normalize(static_cast<float>(std::cos(phi) * sinT) * t +
                                             static_cast<float>(std::sin(phi) * sinT) * b +
                                             static_cast<float>(cosT) * n);
        const RadianceSample s = radiance(origin, dir, depth, mix64(key ^ 0x5851f42d4c957f2dULL));
        ++est.rays;
        if (finite(s.radiance)) c.sum += glm::dvec3(s.radiance);  // a bad sample counts as black
        if (s.distance < std::numeric_limits<float>::infinity())
            c.invDist += 1.0 / std::max(static_cast<double>(s.distance), 1e-9);
        ++c.count;
    };
    for (int j = 0; j < M; ++j)
        for (int k = 0; k < N; ++k) sampleCell(j, k);

    // Supersampling (Radiance's -as): the marginal gain of one more sample in a cell is about
    // variance / count^2; the variance is guessed from the neighbours' brightness differences.
    if (supersamples > 0 && M * N > 1) {
        auto error = [&](int j, int k) {
            const double c = bright(cells[static_cast<std::size_t>(j) * N + k].mean());
            double sum2 = 0.0;
            int neighbours = 0;
            auto add = [&](int jj, int kk) {
                const double d = c - bright(cells[static_cast<std::size_t>(jj) * N + kk].mean());
                sum2 += d * d;
                ++neighbours;
            };
            if (j > 0) add(j - 1, k);
            if (j + 1 < M) add(j + 1, k);
            if (N > 1) {
                add(j, (k + N - 1) % N);
                add(j, (k + 1) % N);
            }
            const double count = cells[static_cast<std::size_t>(j) * N + k].count;
            return neighbours > 0 ? sum2 / neighbours / (count * count) : 0.0;
        };
        // Largest error first; ties go to the lower cell index, so the order is fixed.
        using Entry = std::pair<double, int>;
        auto lower = [](const Entry& a, const Entry& c) {
            return a.first < c.first || (a.first == c.first && a.second > c.second);
        };
        std::priority_queue<Entry, std::vector<Entry>, decltype(lower)> queue(lower);
        for (int i = 0; i < M * N; ++i) queue.push({error(i / N, i % N), i});
        for (int s = 0; s < supersamples; ++s) {
            const int i = queue.top().second;
            queue.pop();
            sampleCell(i / N, i % N);
            queue.push({error(i / N, i % N), i});
        }
    }

    // E = pi / (M N) sum L_jk: each cell holds 1 / (M N) of the cosine-weighted measure.
    const double cellWeight = kPi / (static_cast<double>(M) * N);
    glm::dvec3 e(0.0);
    double invDistSum = 0.0;
    for (const Cell& c : cells) {
        e += c.mean();
        invDistSum += c.meanInvDist();
    }
    est.irradiance = glm::vec3(e * cellWeight);
    est.harmonicDistance = invDistSum > 0.0 ? static_cast<float>(static_cast<double>(M) * N / invDistSum)
                                            : std::numeric_limits<float>::infinity();

    // Ward & Heckbert 1992. Rotational: dE/d(rotation about a) = a . pi/(MN) sum_k v_k sum_j
    // tan(theta_j) L_jk, with v_k the tangent direction at phi_k + pi/2 (column centre).
    // Translational: for each phi column k, the theta boundaries (radial, along u at the column
    // centre) and the phi boundary at phi_k (along v there), each difference divided by the
    // nearer of the two distances.
    glm::dvec3 gradR[3] = {}, gradT[3] = {};
    for (int k = 0; k < N; ++k) {
        const double phiC = 2.0 * kPi * (k + 0.5) / N, phiB = 2.0 * kPi * k / N;
        const glm::dvec3 uC = std::cos(phiC) * glm::dvec3(t) + std::sin(phiC) * glm::dvec3(b);
        const glm::dvec3 vC = -std::sin(phiC) * glm::dvec3(t) + std::cos(phiC) * glm::dvec3(b);
        const glm::dvec3 vB = -std::sin(phiB) * glm::dvec3(t) + std::cos(phiB) * glm::dvec3(b);
        glm::dvec3 rot(0.0), radial(0.0), around(0.0);
        for (int j = 0; j < M; ++j) {
            const Cell& c = cells[static_cast<std::size_t>(j) * N + k];
            const glm::dvec3 L = c.mean();
            rot += meanTan(j, M) * L;
            const double sinLo = std::sqrt(static_cast<double>(j) / M);
            if (j > 0) {
                const Cell& up = cells[static_cast<std::size_t>(j - 1) * N + k];
                const double inv = std::max(c.meanInvDist(), up.meanInvDist());  // 1 / min(R)
                radial += (sinLo * (1.0 - static_cast<double>(j) / M) * inv) * (L - up.mean());
            }
            if (N > 1) {
                const Cell& prev = cells[static_cast<std::size_t>(j) * N + (k + N - 1) % N];
                const double inv = std::max(c.meanInvDist(), prev.meanInvDist());
                const double sinHi = std::sqrt(static_cast<double>(j + 1) / M);
                around += ((sinHi - sinLo) * inv) * (L - prev.mean());
            }
        }
        radial *= 2.0 * kPi / N;
        for (int ch = 0; ch < 3; ++ch) {
            gradR[ch] += vC * (rot[ch] * cellWeight);
            gradT[ch] += uC * radial[ch] + vB * around[ch];
        }
    }
    for (int ch = 0; ch < 3; ++ch) {
        est.gradR[ch] = glm::vec3(gradR[ch]);
        est.gradT[ch] = glm::vec3(gradT[ch]);
    }
    return est;
}

}  // namespace aamap

#pragma once
// A piecewise-constant 2D distribution over a W x H grid of non-negative weights (the environment
// map's importance): a marginal CDF over the rows and one conditional CDF per row, sampled by
// inversion (pbrt's Distribution2D). Inversion keeps a stratified [0,1)^2 pattern stratified over
// the grid. Built in double, stored in float. A guide table per CDF (the interval holding k / n)
// makes an inversion a step or two instead of a binary search.
#include <cstddef>
#include <vector>

#include <glm/vec2.hpp>

namespace aamap {

class Distribution2D {
public:
    // weights: row-major, width * height entries, each >= 0 (negative and non-finite count as 0).
    Distribution2D(const std::vector<float>& weights, int width, int height);

    int width() const { return width_; }
    int height() const { return height_; }
    // True when every weight is zero: nothing can be sampled (sample() returns pdf 0).
    bool empty() const { return empty_; }

    struct Sample {
        glm::vec2 point;  // in [0,1)^2: x along the columns, y along the rows
        int column, row;  // the cell holding it
        float pdf;        // density over [0,1)^2 (W H weight / sum of weights); 0 only when empty()
    };
    // u in [0,1)^2: u.y picks the row on the marginal CDF, u.x the column in that row.
    Sample sample(glm::vec2 u) const;
    // Density over [0,1)^2 of the cell (column, row), as sample() reports it.
    float pdf(int column, int row) const;

    // The tables sample() reads, for code that inverts them itself (path mode's SIMD lanes).
    const std::vector<float>& marginalCdf() const { return marginal_; }
    const std::vector<float>& conditionalCdfs() const { return conditional_; }
    const std::vector<int>& marginalGuide() const { return marginalGuide_; }
    const std::vector<int>& conditionalGuide() const { return conditionalGuide_; }

private:
    int width_, height_;
    bool empty_ = true;
    double scale_ = 0.0;              // W H / sum of weights
    std::vector<float> weights_;      // sanitised copy
    std::vector<float> marginal_;     // height + 1 entries, 0 .. 1
    std::vector<float> conditional_;  // height rows of width + 1 entries, 0 .. 1 (uniform for an empty row)
    std::vector<int> marginalGuide_;     // height entries: where the search for u starts (buildGuide)
    std::vector<int> conditionalGuide_;  // height rows of width entries
};

}  // namespace aamap

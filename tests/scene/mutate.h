#pragma once
// Deterministic random edits of text, for the never-crash tests.
#include <random>
#include <string>

namespace aamap::test {

inline std::string mutate(std::string text, std::mt19937& rng, const std::string& alphabet) {
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits && !text.empty(); ++e) {
        const std::size_t at = rng() % text.size();
        switch (rng() % 3) {
            case 0: text[at] = alphabet[rng() % alphabet.size()]; break;
            case 1: text.insert(at, 1, alphabet[rng() % alphabet.size()]); break;
            default: text.erase(at, 1 + rng() % 6);
        }
    }
    return text;
}

}  // namespace aamap::test

#pragma once
// A whole text file as a string (reports, CSV and results written by the code under test).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace aamap::test {

inline std::string readText(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace aamap::test

#pragma once
// A light validating pass over OBJ and MTL text before tinyobjloader sees it. tinyobjloader is
// lenient (atof on garbage gives 0, out-of-range indices are not checked), so this pass is what
// turns bad input into an InputError naming the file, line and column.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace aamap::detail {

struct ObjPrescan {
    std::vector<std::string> mtllibs;  // names as written after `mtllib`
    std::size_t positions = 0, uvs = 0, normals = 0, faces = 0;
};

// Throws InputError on a malformed number, a non-finite coordinate, or a face index that is zero
// or out of range.
ObjPrescan prescanObj(const std::filesystem::path& file, std::string_view text);

// Throws InputError on a malformed number in a material statement.
void prescanMtl(const std::filesystem::path& file, std::string_view text);

}  // namespace aamap::detail

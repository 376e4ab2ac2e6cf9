#pragma once
// Radiance view options and view files (rview/rpict -v options, rpict's VIEW= header lines).
//
// Accepted per line: `rview ...`, `rpict ...` (other programs' options and arguments are skipped),
// `VIEW= ...`, or bare options. Options: -vtv -vp x y z -vd x y z -vu x y z -vh a -vv a -vs a
// -vl a -vo d -va d (clipping, ignored) -vf file (start from another view file's last view) and
// -vn name (ours, not Radiance's). Later options override earlier ones; unspecified values take
// Radiance's defaults (-vp 0 0 0 -vd 0 1 0 -vu 0 0 1 -vh 45 -vv 45), not View's.
// A view's name is -vn, else a trailing `# comment` on its line, else "<file stem>:<index>".
#include <filesystem>
#include <string_view>
#include <utility>
#include <vector>

#include "scene/scene.h"

namespace aamap {

// Parses one line of view options. `line` (1-based, 0 if unknown) and the token columns go into
// any InputError. Throws for other view types ("view type -vtl is not supported (only -vtv)"),
// unknown -v options, malformed or missing numbers, a zero -vd, -vu parallel to -vd, and field
// angles outside (0, 180).
View parseViewOptions(std::string_view text, const std::filesystem::path& file = {}, int line = 0);

// All views in a view file's text, one per non-comment line; `file` is used for names and errors.
std::vector<View> parseViewText(std::string_view text, const std::filesystem::path& file);

// Reads a view file; throws InputError if it is missing, unreadable, or holds no view.
std::vector<View> loadViewFile(const std::filesystem::path& file);

// rpict -pa 1 fitting: the largest resolution within maxWidth x maxHeight whose pixels are square
// for the view, shrinking one dimension to the ratio tan(vh/2) : tan(vv/2). Throws
// std::invalid_argument for a non-positive maximum.
std::pair<int, int> fitResolution(const View& view, int maxWidth, int maxHeight);

}  // namespace aamap

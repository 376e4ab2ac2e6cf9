#pragma once
// The bytes of an input file as a digest, for the render cache keys: editing a scene or view file
// in place must re-trace what it changes, not reuse images of its old contents.
#include <filesystem>
#include <string>

namespace aamap {

// FNV-1a 64 of the file's bytes, 16 hex digits; "unreadable" when it cannot be read (loading it
// fails later with its own error). Read afresh every time: a digest remembered by modification
// time would miss an edit within the file system's timestamp granularity.
std::string fileDigest(const std::filesystem::path& file);

}  // namespace aamap

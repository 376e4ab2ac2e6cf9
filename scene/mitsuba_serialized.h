#pragma once
// Mitsuba's own mesh format, .serialized (versions 3 and 4, the ones Mitsuba 0.5 to 3.6 write):
// a little-endian header (0x041C, version) before each mesh's zlib stream of flags, name (v4),
// vertex and face counts, positions, optional normals, uvs and colours (single or double
// precision) and uint32 triangles; the file ends with each mesh's offset and the mesh count, which
// is how shape_index finds a mesh other than the first.
#include <cstddef>
#include <filesystem>
#include <span>

#include "scene/mitsuba_shapes.h"

namespace aamap::mitsuba {

// Mesh `shapeIndex` of a .serialized file's bytes, in its local frame. A mesh without normals gets
// angle-weighted vertex normals as Mitsuba computes them, unless faceNormals (then normals stay
// empty). Colours are read past. Throws InputError naming `file` and what is wrong: bad magic or
// version, a shape index out of range, a truncated file, a stream zlib cannot inflate, counts the
// data does not hold, or a triangle naming a vertex that does not exist.
ShapeMesh parseSerialized(std::span<const std::byte> bytes, const std::filesystem::path& file, int shapeIndex,
                          bool faceNormals);
// The same, reading the file.
ShapeMesh readSerialized(const std::filesystem::path& file, int shapeIndex, bool faceNormals);

}  // namespace aamap::mitsuba

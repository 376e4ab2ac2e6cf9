#include "scene/mitsuba_serialized.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <zlib.h>

#include "core/error.h"

namespace aamap::mitsuba {
namespace fs = std::filesystem;

namespace {

constexpr std::uint16_t kMagic = 0x041C;
constexpr std::uint16_t kVersion3 = 3;
constexpr std::uint16_t kVersion4 = 4;
constexpr std::uint32_t kHasNormals = 0x0001;
constexpr std::uint32_t kHasUvs = 0x0002;
constexpr std::uint32_t kHasColours = 0x0008;
constexpr std::uint32_t kDoublePrecision = 0x2000;
// A bound on one mesh's inflated size, so that a corrupt or hostile stream cannot exhaust memory.
constexpr std::size_t kMaxInflated = std::size_t{1} << 32;

[[noreturn]] void bad(const fs::path& file, const std::string& problem) {
    throw InputError(file, fmt::format("serialized mesh: {}", problem));
}

template <typename T>
T readLittle(std::span<const std::byte> bytes, std::size_t at) {
    // Little endian on disk; every platform aamap builds for is little endian too.
    T value;
    std::memcpy(&value, bytes.data() + at, sizeof(T));
    return value;
}

// The zlib stream that starts at `at`, inflated up to its end marker.
std::vector<std::byte> inflateStream(std::span<const std::byte> bytes, std::size_t at, const fs::path& file,
                                     int shapeIndex) {
    z_stream z{};
    if (inflateInit(&z) != Z_OK) bad(file, "zlib could not start");
    // A guess that grows by doubling: the stream's length is known only once it ends.
    std::vector<std::byte> out(std::clamp<std::size_t>(4 * (bytes.size() - at), 4096, std::size_t{1} << 26));
    z.next_in = reinterpret_cast<Bytef*>(const_cast<std::byte*>(bytes.data() + at));
    z.avail_in = static_cast<uInt>(std::min<std::size_t>(bytes.size() - at, std::numeric_limits<uInt>::max()));
    std::size_t produced = 0;
    for (;;) {
        if (produced == out.size()) {
            if (out.size() >= kMaxInflated) {
                inflateEnd(&z);
                bad(file, fmt::format("mesh {} inflates to more than {} bytes", shapeIndex, kMaxInflated));
            }
            out.resize(std::min(2 * out.size(), kMaxInflated));
        }
        const std::size_t room = std::min<std::size_t>(out.size() - produced, std::numeric_limits<uInt>::max());
        z.next_out = reinterpret_cast<Bytef*>(out.data() + produced);
        z.avail_out = static_cast<uInt>(room);
        const int rc = inflate(&z, Z_NO_FLUSH);
        produced += room - z.avail_out;
        if (rc == Z_STREAM_END) break;
        if (rc == Z_OK) continue;
        const std::string why = rc == Z_BUF_ERROR ? std::string("the file ends inside it (truncated)")
                                                  : std::string(z.msg != nullptr ? z.msg : "corrupt data");
        inflateEnd(&z);
        bad(file, fmt::format("mesh {}'s compressed data cannot be inflated: {}", shapeIndex, why));
    }
    inflateEnd(&z);
    out.resize(produced);
    return out;
}

// Reads the inflated stream front to back; running past its end is a truncated mesh.
class Cursor {
public:
    Cursor(const std::vector<std::byte>& data, const fs::path& file, int shapeIndex)
        : data_(data), file_(file), shapeIndex_(shapeIndex) {}

    template <typename T>
    T get(const char* what) {
        need(sizeof(T), what);
        T v = readLittle<T>(data_, at_);
        at_ += sizeof(T);
        return v;
    }
    // `count` reals of either precision, as floats; dst == nullptr skips them.
    void reals(std::uint64_t count, bool doublePrecision, float* dst, const char* what) {
        const std::size_t size = doublePrecision ? 8 : 4;
        if (count > (data_.size() - at_) / size) truncated(what);
        for (std::uint64_t i = 0; i < count && dst != nullptr; ++i)
            dst[i] = doublePrecision ? static_cast<float>(readLittle<double>(data_, at_ + i * 8))
                                     : readLittle<float>(data_, at_ + i * 4);
        at_ += count * size;
    }
    std::size_t left() const { return data_.size() - at_; }
    [[noreturn]] void truncated(const char* what) const {
        bad(file_, fmt::format("mesh {} is truncated: its data ends before the {}", shapeIndex_, what));
    }

private:
    void need(std::size_t n, const char* what) const {
        if (n > data_.size() - at_) truncated(what);
    }
    std::span<const std::byte> data_;
    const fs::path& file_;
    int shapeIndex_;
    std::size_t at_ = 0;
};

// Mitsuba's normals for a mesh without them: each face's normal weighted by its corner's angle.
void angleWeightedNormals(ShapeMesh& m) {
    m.normals.assign(m.positions.size(), glm::vec3(0.0f));
    for (const glm::uvec3& t : m.triangles) {
        const glm::vec3 p[3] = {m.positions[t.x], m.positions[t.y], m.positions[t.z]};
        const glm::vec3 c = glm::cross(p[1] - p[0], p[2] - p[0]);
        const float len = glm::length(c);
        if (!(len > 0.0f)) continue;
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 a = glm::normalize(p[(k + 1) % 3] - p[k]);
            const glm::vec3 b = glm::normalize(p[(k + 2) % 3] - p[k]);
            m.normals[t[k]] += (c / len) * std::acos(std::clamp(glm::dot(a, b), -1.0f, 1.0f));
        }
    }
    // A vertex no face uses keeps a zero normal, which appendShape replaces by the face's.
    for (glm::vec3& n : m.normals)
        if (const float l = glm::length(n); l > 0.0f) n /= l;
}

}  // namespace

ShapeMesh parseSerialized(std::span<const std::byte> bytes, const fs::path& file, int shapeIndex, bool faceNormals) {
    if (shapeIndex < 0) bad(file, fmt::format("shape_index {} is negative", shapeIndex));
    if (bytes.size() < 4) bad(file, "the file is too short for its header (truncated)");
    const auto magic = readLittle<std::uint16_t>(bytes, 0);
    const auto version = readLittle<std::uint16_t>(bytes, 2);
    if (magic != kMagic) bad(file, fmt::format("bad magic 0x{:04X} (a .serialized file starts with 0x041C)", magic));
    if (version != kVersion3 && version != kVersion4)
        bad(file, fmt::format("version {} is not supported (3 and 4 are)", version));

    std::size_t offset = 0;
    if (shapeIndex > 0) {
        // The table at the end: one offset per mesh (uint64 in v4, uint32 in v3), then the count.
        if (bytes.size() < 8) bad(file, "the file is too short for its table of meshes (truncated)");
        const auto count = readLittle<std::uint32_t>(bytes, bytes.size() - 4);
        if (static_cast<std::uint32_t>(shapeIndex) >= count)
            bad(file, fmt::format("shape_index {} is out of range: the file holds {} mesh{}", shapeIndex, count,
                                  count == 1 ? "" : "es"));
        const std::size_t entry = version == kVersion4 ? 8 : 4;
        if (count > (bytes.size() - 4) / entry) bad(file, fmt::format("its table of {} meshes does not fit in the file", count));
        const std::size_t at = bytes.size() - 4 - entry * (count - static_cast<std::size_t>(shapeIndex));
        offset = version == kVersion4 ? readLittle<std::uint64_t>(bytes, at) : readLittle<std::uint32_t>(bytes, at);
        if (offset > bytes.size() - 4)
            bad(file, fmt::format("mesh {}'s offset {} lies past the end of the file", shapeIndex, offset));
        if (readLittle<std::uint16_t>(bytes, offset) != kMagic)
            bad(file, fmt::format("mesh {}'s offset {} does not point at a mesh header", shapeIndex, offset));
    }
    if (bytes.size() - offset <= 4) bad(file, fmt::format("mesh {} has no data (truncated)", shapeIndex));

    const std::vector<std::byte> data = inflateStream(bytes, offset + 4, file, shapeIndex);
    Cursor in(data, file, shapeIndex);
    const auto flags = in.get<std::uint32_t>("flags");
    if (version == kVersion4)
        while (in.get<char>("name") != '\0') {
        }
    const auto vertices = in.get<std::uint64_t>("vertex count");
    const auto faces = in.get<std::uint64_t>("face count");
    const bool dp = (flags & kDoublePrecision) != 0;
    const std::size_t real = dp ? 8 : 4;
    // Counts first, against what the stream holds, so that a corrupt count allocates nothing.
    const std::uint64_t perVertex = real * (3 + ((flags & kHasNormals) ? 3 : 0) + ((flags & kHasUvs) ? 2 : 0) +
                                            ((flags & kHasColours) ? 3 : 0));
    if (vertices > in.left() / perVertex || faces > in.left() / 12 || vertices * perVertex + faces * 12 > in.left())
        bad(file, fmt::format("mesh {} is truncated: {} vertices and {} triangles do not fit in its {} bytes", shapeIndex,
                              vertices, faces, in.left()));
    if (vertices > std::numeric_limits<std::uint32_t>::max())
        bad(file, fmt::format("mesh {} has {} vertices, more than 32-bit indices reach", shapeIndex, vertices));

    ShapeMesh m;
    std::vector<float> buffer(vertices * 3);
    in.reals(vertices * 3, dp, buffer.data(), "positions");
    m.positions.resize(vertices);
    for (std::size_t i = 0; i < vertices; ++i) {
        m.positions[i] = {buffer[3 * i], buffer[3 * i + 1], buffer[3 * i + 2]};
        if (!std::isfinite(buffer[3 * i]) || !std::isfinite(buffer[3 * i + 1]) || !std::isfinite(buffer[3 * i + 2]))
            bad(file, fmt::format("mesh {}'s vertex {} is not finite", shapeIndex, i));
    }
    if (flags & kHasNormals) {
        in.reals(vertices * 3, dp, faceNormals ? nullptr : buffer.data(), "normals");
        if (!faceNormals) {
            m.normals.resize(vertices);
            for (std::size_t i = 0; i < vertices; ++i) m.normals[i] = {buffer[3 * i], buffer[3 * i + 1], buffer[3 * i + 2]};
        }
    }
    if (flags & kHasUvs) {
        // Mitsuba's uv as stored: v = 0 is the image's top row in Mitsuba as in aamap.
        in.reals(vertices * 2, dp, buffer.data(), "uvs");
        m.uvs.resize(vertices);
        for (std::size_t i = 0; i < vertices; ++i) m.uvs[i] = {buffer[2 * i], buffer[2 * i + 1]};
    }
    if (flags & kHasColours) in.reals(vertices * 3, dp, nullptr, "colours");
    m.triangles.resize(faces);
    for (std::size_t f = 0; f < faces; ++f) {
        glm::uvec3 t;
        for (int k = 0; k < 3; ++k) t[k] = in.get<std::uint32_t>("triangles");
        if (t.x >= vertices || t.y >= vertices || t.z >= vertices)
            bad(file, fmt::format("mesh {}'s triangle {} uses vertex {} of {}", shapeIndex, f,
                                  std::max({t.x, t.y, t.z}), vertices));
        m.triangles[f] = t;
    }
    if (!faceNormals && m.normals.empty()) angleWeightedNormals(m);
    return m;
}

ShapeMesh readSerialized(const fs::path& file, int shapeIndex, bool faceNormals) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file, "cannot open the serialized mesh");
    std::vector<char> raw((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) throw InputError(file, "cannot read the serialized mesh");
    return parseSerialized(std::as_bytes(std::span<const char>(raw)), file, shapeIndex, faceNormals);
}

}  // namespace aamap::mitsuba

#include "eval/cache_records.h"

#include <fstream>

#include <fmt/format.h>

#include "core/atomic_file.h"
#include "core/error.h"

namespace aamap {
using Json = nlohmann::ordered_json;

Json toJson(const CachedRender& entry) {
    Json j = toJson(entry.record);
    j["render_config"] = entry.renderConfig;
    return j;
}

Json toJson(const PixelFactsRecord& entry) { return {{"key", entry.key}, {"seconds", entry.seconds}}; }

CachedRender cachedRenderFromJson(const Json& j) {
    return {recordFromJson(j), j.value("render_config", Json::object())};
}

PixelFactsRecord pixelFactsRecordFromJson(const Json& j) {
    return {j.at("key").get<std::string>(), j.at("seconds").get<double>()};
}

namespace {

Json readJsonFile(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw EnvironmentError(fmt::format("{}: cannot open", file.string()));
    return Json::parse(in);
}

}  // namespace

CachedRender readCachedRender(const std::filesystem::path& file) { return cachedRenderFromJson(readJsonFile(file)); }
SnapshotRecord readSnapshotRecord(const std::filesystem::path& file) { return snapshotRecordFromJson(readJsonFile(file)); }
PixelFactsRecord readPixelFactsRecord(const std::filesystem::path& file) {
    return pixelFactsRecordFromJson(readJsonFile(file));
}

void writeRecord(const std::filesystem::path& file, const Json& record) {
    writeTextAtomically(file, record.dump(2) + "\n");
}

}  // namespace aamap

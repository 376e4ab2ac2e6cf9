#pragma once
// The record.json of each kind of OUTDIR/cache entry (eval/render_cache.h), typed: the runner
// works on these structs and turns them into JSON only when it reads or writes the file.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "eval/results.h"

namespace aamap {

// A traced render: its record, and the settings its key hashes (renderKeyObject), so that an
// entry says what it is without the config that made it.
struct CachedRender {
    RenderRecord record;
    nlohmann::ordered_json renderConfig;
};

// The pixel facts of a scene, view and size (core/pixel_facts.h): how long tracing them took.
struct PixelFactsRecord {
    std::string key;
    double seconds = 0;
};

nlohmann::ordered_json toJson(const CachedRender& entry);
nlohmann::ordered_json toJson(const PixelFactsRecord& entry);
CachedRender cachedRenderFromJson(const nlohmann::ordered_json& j);
PixelFactsRecord pixelFactsRecordFromJson(const nlohmann::ordered_json& j);

// record.json read and parsed (throws std::exception: a missing, truncated or damaged file), or
// written atomically, pretty-printed.
CachedRender readCachedRender(const std::filesystem::path& file);
SnapshotRecord readSnapshotRecord(const std::filesystem::path& file);
PixelFactsRecord readPixelFactsRecord(const std::filesystem::path& file);
void writeRecord(const std::filesystem::path& file, const nlohmann::ordered_json& record);

}  // namespace aamap

#pragma once
// OUTDIR/cache/<key>/: one folder per finished render (or Snapshot), committed atomically: the
// files are written into <key>.tmp-<pid>-<n>/ and the folder is renamed into place, record.json
// last of all. So a folder under its final name is always complete, and a run killed at any point
// restarts cleanly: the next run removes the stale temporaries and reuses every complete folder.
#include <filesystem>
#include <functional>
#include <string>

namespace aamap {

class RenderCache {
public:
    // Creates the folder if needed and removes temporaries left by killed runs (there and in
    // `cleanAlso`, typically OUTDIR, where core/atomic_file leaves NAME.tmp-PID on a kill).
    explicit RenderCache(std::filesystem::path dir, const std::filesystem::path& cleanAlso = {});

    // A complete entry: the folder exists and holds record.json.
    bool has(const std::string& key) const;
    std::filesystem::path entry(const std::string& key) const { return dir_ / key; }
    std::filesystem::path record(const std::string& key) const { return dir_ / key / "record.json"; }

    // write(tmpDir) fills a fresh folder, which must end up holding record.json; then the folder
    // is renamed to entry(key). An existing entry is replaced. Throws EnvironmentError.
    void commit(const std::string& key, const std::function<void(const std::filesystem::path& tmpDir)>& write);

    int removedTemporaries() const { return removed_; }
    const std::filesystem::path& dir() const { return dir_; }

private:
    std::filesystem::path dir_;
    int removed_ = 0;
};

// Copies a file into place atomically (temporary + rename).
void copyFileAtomically(const std::filesystem::path& from, const std::filesystem::path& to);

}  // namespace aamap

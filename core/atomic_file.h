#pragma once
// Outputs are written to a temporary name in the destination folder and renamed into place,
// so a crash, a full disk or a SIGKILL never leaves a half-written file under the final name.
// Every byte goes through CheckedFile, whose writes are checked (ENOSPC and EIO are errors that
// name the final file, not a silently short file).
//
// Test hook: AAMAP_TEST_WRITE_FAULT=<ENOSPC|EIO>@<bytes> makes this process behave as if the disk
// failed after <bytes> bytes in all (summed over every CheckedFile): the write that crosses the
// limit writes up to it and then fails with that errno, as a filling disk does. Tests only
// (tests/robustness/environment_checks.sh, test_atomic_file.cpp); unset in normal use.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string_view>

namespace aamap {

// A file opened for writing whose every write, the final data sync and the close are checked.
// Errors throw EnvironmentError "<displayPath>: cannot write: <strerror>".
class CheckedFile {
public:
    CheckedFile(const std::filesystem::path& path, const std::filesystem::path& displayPath);
    ~CheckedFile();
    CheckedFile(const CheckedFile&) = delete;
    CheckedFile& operator=(const CheckedFile&) = delete;

    void write(const void* data, std::size_t bytes);
    std::uint64_t position() const { return position_; }
    void seek(std::uint64_t position);
    // fdatasync and close; throws if that or any earlier write failed (also a failure that a
    // library swallowed, e.g. in a destructor).
    void close();
    bool failed() const { return failed_; }

private:
    [[noreturn]] void fail(int err);
    int fd_ = -1;
    std::uint64_t position_ = 0;
    bool failed_ = false;
    int error_ = 0;
    std::filesystem::path display_;
};

// Calls write(tmpPath), then renames tmpPath to path. If write throws, the temporary is removed
// and the exception propagates. Throws EnvironmentError if the rename fails.
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path& tmpPath)>& write);

// The same with a CheckedFile on the temporary: write fills it, the sync and close are checked
// here, then it is renamed into place. On any failure the temporary is removed.
void writeCheckedAtomically(const std::filesystem::path& path, const std::function<void(CheckedFile& file)>& write);

// Convenience for text and byte payloads.
void writeTextAtomically(const std::filesystem::path& path, std::string_view contents);

}  // namespace aamap

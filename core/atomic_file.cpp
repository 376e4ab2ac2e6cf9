#include "core/atomic_file.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <mutex>
#include <string>
#include <unistd.h>

#include <fmt/format.h>

#include "core/error.h"

namespace aamap {
namespace {

// The test hook (see the header): the errno to fail with and the bytes left before it.
struct WriteFault {
    int err = 0;
    std::uint64_t bytesLeft = 0;
};

WriteFault* writeFault() {
    static WriteFault* fault = [] () -> WriteFault* {
        const char* env = std::getenv("AAMAP_TEST_WRITE_FAULT");
        if (!env || !*env) return nullptr;
        const std::string spec(env);
        const std::size_t at = spec.find('@');
        const std::string name = spec.substr(0, at);
        static WriteFault f;
        f.err = name == "EIO" ? EIO : ENOSPC;
        f.bytesLeft = at == std::string::npos ? 0 : std::strtoull(spec.c_str() + at + 1, nullptr, 10);
        return &f;
    }();
    return fault;
}

// How many of `bytes` may be written before the injected fault; all when there is none.
std::size_t allowedByFault(std::size_t bytes, int& err) {
    WriteFault* fault = writeFault();
    if (!fault) return bytes;
    static std::mutex mutex;
    const std::lock_guard lock(mutex);
    const std::size_t allowed = static_cast<std::size_t>(std::min<std::uint64_t>(bytes, fault->bytesLeft));
    fault->bytesLeft -= allowed;
    if (allowed < bytes) err = fault->err;
    return allowed;
}

std::filesystem::path tempPathFor(const std::filesystem::path& path) {
    // Same directory as the target so that rename() is atomic (same file system).
    std::filesystem::path tmp = path;
    tmp += fmt::format(".tmp-{}", ::getpid());
    return tmp;
}

void renameIntoPlace(const std::filesystem::path& tmp, const std::filesystem::path& path) {
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int err = errno;
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throw EnvironmentError(fmt::format("{}: cannot write: {}", path.string(), std::strerror(err)));
    }
}

}  // namespace

CheckedFile::CheckedFile(const std::filesystem::path& path, const std::filesystem::path& displayPath)
    : display_(displayPath) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) fail(errno);
}

CheckedFile::~CheckedFile() {
    if (fd_ >= 0) ::close(fd_);
}

void CheckedFile::fail(int err) {
    failed_ = true;
    if (error_ == 0) error_ = err;
    throw EnvironmentError(fmt::format("{}: cannot write: {}", display_.string(), std::strerror(error_)));
}

void CheckedFile::write(const void* data, std::size_t bytes) {
    if (failed_) fail(error_);
    const char* p = static_cast<const char*>(data);
    int injected = 0;
    std::size_t left = allowedByFault(bytes, injected);
    while (left > 0) {
        const ssize_t n = ::write(fd_, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) fail(n < 0 ? errno : ENOSPC);
        p += n;
        left -= static_cast<std::size_t>(n);
        position_ += static_cast<std::uint64_t>(n);
    }
    if (injected != 0) fail(injected);
}

void CheckedFile::seek(std::uint64_t position) {
    if (failed_) fail(error_);
    if (::lseek(fd_, static_cast<off_t>(position), SEEK_SET) < 0) fail(errno);
    position_ = position;
}

void CheckedFile::close() {
    if (fd_ < 0) return;
    if (failed_) fail(error_);
    // The data sync reports write-back errors (EIO, and ENOSPC on file systems that allocate late)
    // before the rename makes the file visible under its final name.
    const int syncErr = ::fdatasync(fd_) != 0 && errno != EINVAL ? errno : 0;
    const int closeErr = ::close(fd_) != 0 ? errno : 0;
    fd_ = -1;
    if (syncErr != 0) fail(syncErr);
    if (closeErr != 0) fail(closeErr);
}

void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path&)>& write) {
    const std::filesystem::path tmp = tempPathFor(path);
    try {
        write(tmp);
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throw;
    }
    renameIntoPlace(tmp, path);
}

void writeCheckedAtomically(const std::filesystem::path& path, const std::function<void(CheckedFile&)>& write) {
    writeFileAtomically(path, [&](const std::filesystem::path& tmp) {
        CheckedFile file(tmp, path);
        write(file);
        file.close();
    });
}

void writeTextAtomically(const std::filesystem::path& path, std::string_view contents) {
    writeCheckedAtomically(path, [&](CheckedFile& file) { file.write(contents.data(), contents.size()); });
}

}  // namespace aamap

#pragma once
// Errors about the user's input carry the file, line and column they refer to, so that every
// parser reports "file:line:col: what is wrong" in the same shape.
#include <filesystem>
#include <stdexcept>
#include <string>

namespace aamap {

class InputError : public std::runtime_error {
public:
    // line and column are 1-based; 0 means "not applicable" and is left out of the message.
    InputError(std::filesystem::path file, int line, int column, const std::string& problem);
    InputError(std::filesystem::path file, const std::string& problem) : InputError(std::move(file), 0, 0, problem) {}

    const std::filesystem::path& file() const { return file_; }
    int line() const { return line_; }
    int column() const { return column_; }
    const std::string& problem() const { return problem_; }

private:
    std::filesystem::path file_;
    int line_;
    int column_;
    std::string problem_;
};

// Failures of the environment rather than of the input: no Vulkan device, disk full, ...
class EnvironmentError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The user named a device (--device, AAMAP_DEVICE) that is absent or unusable: an error, never a
// reason to fall back to the CPU path, since the user asked for that device.
class RequestedDeviceError : public EnvironmentError {
public:
    using EnvironmentError::EnvironmentError;
};

}  // namespace aamap

#include "core/log.h"

#include <algorithm>
#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/sinks/stdout_color_sinks.h>

namespace aamap {

void initLogging(spdlog::level::level_enum level) {
    spdlog::drop("aamap");  // calling twice (tests) must not throw "logger exists"
    auto logger = spdlog::stderr_color_mt("aamap");
    logger->set_pattern("[%T.%e] [%^%l%$] %v");
    logger->set_level(level);
    spdlog::set_default_logger(std::move(logger));
}

Progress::Progress(std::string label, int total)
    : label_(std::move(label)),
      total_(std::max(1, total)),
      interactive_(::isatty(::fileno(stderr)) != 0 && spdlog::should_log(spdlog::level::info)),
      start_(std::chrono::steady_clock::now()),
      lastPrint_(start_) {}

Progress::~Progress() {
    // Abandoned (an exception unwound past it): end the bar's line, but do not claim "done".
    if (!finished_ && interactive_) fmt::print(stderr, "\n");
}

void Progress::update(int done, int total) {
    std::lock_guard lock(mutex_);
    total_ = std::max(1, total);
    advance(done);
}

void Progress::update(int done) {
    std::lock_guard lock(mutex_);
    advance(done);
}

void Progress::advance(int done) {
    if (finished_ || done <= done_) return;
    done_ = std::min(done, total_);
    // A bar redraws at most 10 times a second; log lines come at most every 5 seconds.
    const auto now = std::chrono::steady_clock::now();
    const auto interval = interactive_ ? std::chrono::milliseconds(100) : std::chrono::milliseconds(5000);
    if (now - lastPrint_ < interval) return;
    lastPrint_ = now;
    print(false);
}

void Progress::finish() {
    std::lock_guard lock(mutex_);
    if (finished_) return;
    finished_ = true;
    done_ = total_;
    print(true);
}

void Progress::print(bool final) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const int percent = done_ * 100 / total_;
    if (interactive_) {
        constexpr int kWidth = 30;
        const int filled = done_ * kWidth / total_;
        const std::string bar = std::string(filled, '#') + std::string(kWidth - filled, ' ');
        fmt::print(stderr, "\r{} [{}] {:3}% {:.1f} s{}", label_, bar, percent, seconds, final ? "\n" : "");
        std::fflush(stderr);
    } else if (!final) {
        spdlog::info("{}: {}% ({}/{}) after {:.1f} s", label_, percent, done_, total_, seconds);
    } else {
        spdlog::info("{}: done in {:.2f} s", label_, seconds);
    }
}

}  // namespace aamap

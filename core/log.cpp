#include "core/log.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <utility>
#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/sinks/ansicolor_sink.h>
#include <spdlog/sinks/base_sink.h>

namespace aamap {
namespace {

// The bar currently on the terminal's last line, shared by Progress and the log sink. One bar at
// a time is enough: renders are traced one after another.
struct TerminalBar {
    std::mutex mutex;
    std::FILE* out = stderr;
    std::string line;  // what the bar shows now; empty: no bar on screen
};

TerminalBar& terminalBar() {
    static TerminalBar bar;
    return bar;
}

// Forwards to a colour sink, but first clears a bar that is on screen and redraws it after the
// message, so a warning during a trace reads as a line of its own.
class BarAwareSink final : public spdlog::sinks::base_sink<std::mutex> {
public:
    explicit BarAwareSink(std::FILE* out) : out_(out), inner_(out, spdlog::color_mode::automatic) {
        inner_.set_pattern("[%T.%e] [%^%l%$] %v");
    }

protected:
    void sink_it_(const spdlog::details::log_msg& msg) override {
        TerminalBar& bar = terminalBar();
        std::lock_guard lock(bar.mutex);
        const bool barShown = !bar.line.empty() && bar.out == out_;
        if (barShown) std::fputs("\r\x1b[2K", out_);
        inner_.log(msg);
        if (barShown) {
            std::fputs(bar.line.c_str(), out_);
            std::fflush(out_);
        }
    }
    void flush_() override { inner_.flush(); }
    void set_pattern_(const std::string& pattern) override { inner_.set_pattern(pattern); }

private:
    std::FILE* out_;
    spdlog::sinks::ansicolor_sink<spdlog::details::console_nullmutex> inner_;
};

}  // namespace

void initLogging(spdlog::level::level_enum level, std::FILE* out) {
    spdlog::drop("aamap");  // calling twice (tests) must not throw "logger exists"
    auto logger = std::make_shared<spdlog::logger>("aamap", std::make_shared<BarAwareSink>(out));
    logger->set_level(level);
    spdlog::register_logger(logger);
    spdlog::set_default_logger(std::move(logger));
    std::lock_guard lock(terminalBar().mutex);
    terminalBar().out = out;
}

struct WarningCapture::Sink final : spdlog::sinks::base_sink<std::mutex> {
    std::vector<std::pair<std::string, int>> drain() {
        std::lock_guard lock(mutex_);
        return std::exchange(messages, {});
    }

protected:
    std::vector<std::pair<std::string, int>> messages;  // in first-seen order, with their counts

    void sink_it_(const spdlog::details::log_msg& msg) override {
        if (msg.level < spdlog::level::warn) return;
        std::string text(msg.payload.data(), msg.payload.size());
        const auto it = std::find_if(messages.begin(), messages.end(), [&](const auto& m) { return m.first == text; });
        if (it != messages.end()) ++it->second;
        else messages.emplace_back(std::move(text), 1);
    }
    void flush_() override {}
};

WarningCapture::WarningCapture() : sink_(std::make_shared<Sink>()) { spdlog::default_logger()->sinks().push_back(sink_); }

WarningCapture::~WarningCapture() {
    auto& sinks = spdlog::default_logger()->sinks();
    sinks.erase(std::remove(sinks.begin(), sinks.end(), sink_), sinks.end());
}

std::vector<std::string> WarningCapture::take() {
    std::vector<std::string> out;
    auto messages = sink_->drain();
    for (auto& [text, count] : messages) out.push_back(count > 1 ? fmt::format("{} ({} times)", text, count) : std::move(text));
    return out;
}

std::optional<double> secondsLeft(int done, int total, double elapsed) {
    if (done <= 0 || total <= 0) return std::nullopt;
    return elapsed * static_cast<double>(std::max(0, total - done)) / static_cast<double>(done);
}

std::string formatDuration(double seconds) {
    seconds = std::max(0.0, seconds);
    if (seconds < 10.0) return fmt::format("{:.1f} s", seconds);
    const long s = std::lround(seconds);
    if (s < 60) return fmt::format("{} s", s);
    if (s < 3600) return fmt::format("{} min {:02} s", s / 60, s % 60);
    return fmt::format("{} h {:02} min", s / 3600, (s % 3600) / 60);
}

void WorkEstimate::plan(double units, int jobs) {
    plannedUnits_ += std::max(0.0, units);
    jobsPlanned_ += std::max(0, jobs);
}

void WorkEstimate::finished(double units, double seconds) {
    doneUnits_ += std::max(0.0, units);
    seconds_ += std::max(0.0, seconds);
    ++jobsDone_;
}

std::optional<double> WorkEstimate::secondsLeft() const {
    if (!(doneUnits_ > 0)) return std::nullopt;
    return seconds_ / doneUnits_ * std::max(0.0, plannedUnits_ - doneUnits_);
}

std::string WorkEstimate::text() const {
    std::string text = fmt::format("run: {} of {} traces done", jobsDone_, jobsPlanned_);
    if (jobsDone_ < jobsPlanned_)
        if (const std::optional<double> left = secondsLeft()) text += fmt::format(", about {} left", formatDuration(*left));
    return text;
}

std::string progressText(const std::string& label, int done, int total, double elapsed) {
    total = std::max(1, total);
    std::string text = fmt::format("{} {}% ({}/{}), {}", label, done * 100 / total, done, total, formatDuration(elapsed));
    if (done < total)
        if (const std::optional<double> left = secondsLeft(done, total, elapsed))
            text += fmt::format(", about {} left", formatDuration(*left));
    return text;
}

Progress::Progress(std::string label, int total)
    : label_(std::move(label)),
      total_(std::max(1, total)),
      interactive_(::isatty(::fileno(terminalBar().out)) != 0 && spdlog::should_log(spdlog::level::info)),
      start_(std::chrono::steady_clock::now()),
      lastPrint_(start_) {}

Progress::~Progress() {
    // Abandoned (an exception unwound past it): end the bar's line, but do not claim "done".
    if (!finished_ && interactive_) {
        TerminalBar& bar = terminalBar();
        std::lock_guard lock(bar.mutex);
        if (!bar.line.empty()) std::fputs("\n", bar.out);
        bar.line.clear();
    }
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
    if (interactive_) {
        constexpr int kWidth = 30;
        const int filled = done_ * kWidth / total_;
        const std::string line = fmt::format("\r[{}{}] {}", std::string(filled, '#'), std::string(kWidth - filled, ' '),
                                             progressText(label_, done_, total_, seconds));
        TerminalBar& bar = terminalBar();
        std::lock_guard lock(bar.mutex);
        std::fputs(("\r\x1b[2K" + line.substr(1) + (final ? "\n" : "")).c_str(), bar.out);
        std::fflush(bar.out);
        bar.line = final ? std::string() : line.substr(1);
    } else if (!final) {
        spdlog::info("{}", progressText(label_, done_, total_, seconds));
    } else {
        spdlog::info("{}: done in {}", label_, formatDuration(seconds));
    }
}

}  // namespace aamap

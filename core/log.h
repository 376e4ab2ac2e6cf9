#pragma once
// Logging goes to stderr (results go to files). Progress is a \r-updated bar on a terminal and
// plain periodic log lines otherwise, so CI logs stay readable. On a terminal, a log line that
// arrives while a bar is showing clears the bar, prints on its own line and redraws the bar
// below it, so messages never land in the middle of a bar.
#include <chrono>
#include <cstdio>
#include <mutex>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

namespace aamap {

// Installs a logger on `out` (stderr by default) as spdlog's default. Call once at start-up;
// calling again replaces it (tests).
void initLogging(spdlog::level::level_enum level = spdlog::level::info, std::FILE* out = stderr);

// Collects the warnings (and errors) logged anywhere while it is alive, in order, each once with
// how often it came: what a scene loader said, for the report's problems box. They are still
// logged as usual. One at a time; construct and destroy it on the thread that owns the logger.
class WarningCapture {
public:
    WarningCapture();
    ~WarningCapture();
    WarningCapture(const WarningCapture&) = delete;
    WarningCapture& operator=(const WarningCapture&) = delete;
    // The messages so far ("message (3 times)" for a repeated one), and forgets them.
    std::vector<std::string> take();

private:
    struct Sink;
    std::shared_ptr<Sink> sink_;
};

// Seconds left for `done` of `total` items after `elapsed` seconds at the rate so far; nullopt
// while nothing is done yet (no rate to go by).
std::optional<double> secondsLeft(int done, int total, double elapsed);

// Time left for a whole run of jobs of unequal size (renders of different rays per pixel): each
// job's size is an estimate in common units (its ray budget), and the rate in seconds per unit
// comes from the jobs finished so far. Not thread-safe; the runner calls it between jobs.
class WorkEstimate {
public:
    void plan(double units, int jobs = 1);
    void finished(double units, double seconds);
    int jobsPlanned() const { return jobsPlanned_; }
    int jobsDone() const { return jobsDone_; }
    // nullopt until a timed job with a non-zero size has finished.
    std::optional<double> secondsLeft() const;
    // "run: 3 of 8 traces done, about 2 min 10 s left".
    std::string text() const;

private:
    double plannedUnits_ = 0, doneUnits_ = 0, seconds_ = 0;
    int jobsPlanned_ = 0, jobsDone_ = 0;
};

// "12 s", "3 min 05 s", "2 h 04 min": a duration as a person reads it.
std::string formatDuration(double seconds);

// One progress line, without the bar: "label 42% (21/50), 3.1 s, about 4.3 s left".
std::string progressText(const std::string& label, int done, int total, double elapsed);

class Progress {
public:
    // label: what is being done ("trace uniform"); total: the number of work items (tiles), or
    // 0 if it is only known when the first update() arrives.
    explicit Progress(std::string label, int total = 0);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    // Thread-safe; done may arrive out of order from worker threads, the largest value wins.
    void update(int done);
    void update(int done, int total);
    void finish();

    // Forces the mode (tests); by default a bar when stderr is a terminal.
    void setInteractive(bool interactive) { interactive_ = interactive; }

private:
    void advance(int done);  // with mutex_ held
    void print(bool final);

    std::string label_;
    int total_;
    int done_ = 0;
    bool interactive_;
    bool finished_ = false;
    std::mutex mutex_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point lastPrint_;
};

}  // namespace aamap

#pragma once
// Logging goes to stderr (results go to files). Progress is a \r-updated bar on a terminal and
// plain periodic log lines otherwise, so CI logs stay readable.
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

#include <spdlog/spdlog.h>

namespace aamap {

// Installs a stderr logger as spdlog's default. Call once at start-up.
void initLogging(spdlog::level::level_enum level = spdlog::level::info);

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

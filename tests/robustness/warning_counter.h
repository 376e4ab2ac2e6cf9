#pragma once
// Counts the warnings the loaders log through spdlog (the default logger), for tests that demand
// "success with a counted warning".
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

namespace aamap::test {

class WarningCounter {
public:
    WarningCounter() : sink_(std::make_shared<Sink>()), previous_(spdlog::default_logger()) {
        auto logger = std::make_shared<spdlog::logger>("warning-counter", sink_);
        logger->set_level(spdlog::level::warn);
        spdlog::set_default_logger(logger);
    }
    ~WarningCounter() { spdlog::set_default_logger(previous_); }
    WarningCounter(const WarningCounter&) = delete;
    WarningCounter& operator=(const WarningCounter&) = delete;

    std::vector<std::string> messages() const {
        std::lock_guard lock(sink_->guard);
        return sink_->messages;
    }

private:
    struct Sink : spdlog::sinks::base_sink<std::mutex> {
        mutable std::mutex guard;
        std::vector<std::string> messages;
        void sink_it_(const spdlog::details::log_msg& msg) override {
            if (msg.level < spdlog::level::warn) return;
            std::lock_guard lock(guard);
            messages.emplace_back(msg.payload.data(), msg.payload.size());
        }
        void flush_() override {}
    };
    std::shared_ptr<Sink> sink_;
    std::shared_ptr<spdlog::logger> previous_;
};

}  // namespace aamap::test

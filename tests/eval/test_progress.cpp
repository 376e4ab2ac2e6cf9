// Progress: time left from the rate so far, durations as people read them, and a terminal bar
// that log lines never break (a message clears the bar, prints, and the bar is drawn again).
#include <chrono>
#include <cstdio>
#include <thread>
#include <string>

#include <gtest/gtest.h>

#include "core/log.h"

namespace aamap {
namespace {

TEST(Progress, TimeLeftFollowsTheRateSoFar) {
    EXPECT_FALSE(secondsLeft(0, 10, 5.0).has_value());  // no rate yet
    EXPECT_DOUBLE_EQ(*secondsLeft(1, 4, 2.0), 6.0);
    EXPECT_DOUBLE_EQ(*secondsLeft(5, 10, 3.0), 3.0);
    EXPECT_DOUBLE_EQ(*secondsLeft(10, 10, 3.0), 0.0);
}

TEST(Progress, RunTimeLeftWeighsJobsByTheirSize) {
    WorkEstimate run;
    run.plan(4);       // a 4-rpp trace
    run.plan(16);      // a 16-rpp trace
    run.plan(128, 2);  // a 64-rpp trace, timed twice
    EXPECT_EQ(run.jobsPlanned(), 4);
    EXPECT_FALSE(run.secondsLeft().has_value());  // no rate yet
    run.finished(4, 2.0);                         // 0.5 s a unit
    ASSERT_TRUE(run.secondsLeft().has_value());
    EXPECT_DOUBLE_EQ(*run.secondsLeft(), 0.5 * (148 - 4));
    EXPECT_EQ(run.text(), "run: 1 of 4 traces done, about 1 min 12 s left");
    run.finished(16, 6.0);  // now 8 s for 20 units
    EXPECT_DOUBLE_EQ(*run.secondsLeft(), 8.0 / 20.0 * 128);
    run.finished(64, 1.0);
    run.finished(64, 1.0);
    EXPECT_DOUBLE_EQ(*run.secondsLeft(), 0.0);
    EXPECT_EQ(run.text(), "run: 4 of 4 traces done");
}

TEST(Progress, DurationsReadAsPeopleWriteThem) {
    EXPECT_EQ(formatDuration(3.14), "3.1 s");
    EXPECT_EQ(formatDuration(42.4), "42 s");
    EXPECT_EQ(formatDuration(185), "3 min 05 s");
    EXPECT_EQ(formatDuration(7440), "2 h 04 min");
    EXPECT_EQ(progressText("trace x", 1, 4, 2.0), "trace x 25% (1/4), 2.0 s, about 6.0 s left");
    EXPECT_EQ(progressText("trace x", 4, 4, 2.0), "trace x 100% (4/4), 2.0 s");
}

TEST(Progress, LogLinesDoNotBreakTheBar) {
    std::FILE* out = std::tmpfile();
    ASSERT_NE(out, nullptr);
    initLogging(spdlog::level::info, out);
    {
        Progress progress("trace x", 4);
        progress.setInteractive(true);
        progress.finish();  // prints the final bar line
    }
    std::string text;
    {
        Progress progress("trace y", 1000);
        progress.setInteractive(true);
        std::this_thread::sleep_for(std::chrono::milliseconds(150));  // a bar redraws at most every 100 ms
        progress.update(5);
        spdlog::warn("a message during the trace");
        progress.finish();
    }
    std::fflush(out);
    std::rewind(out);
    for (int c; (c = std::fgetc(out)) != EOF;) text.push_back(static_cast<char>(c));
    std::fclose(out);
    initLogging(spdlog::level::info);
    // The bar was on screen; the message returned to the start of the line and erased it first
    // (what follows the last carriage return holds no bar), and the bar came back after it.
    const std::size_t bar = text.find("trace y 0% (5/1000)");
    const std::size_t msg = text.find("a message during the trace");
    ASSERT_NE(bar, std::string::npos) << text;
    ASSERT_NE(msg, std::string::npos) << text;
    ASSERT_LT(bar, msg);
    const std::size_t cr = text.rfind('\r', msg);
    ASSERT_NE(cr, std::string::npos);
    ASSERT_GT(cr, bar);
    EXPECT_EQ(text.substr(cr, 5), "\r\x1b[2K");
    EXPECT_EQ(text.substr(cr, msg - cr).find("trace y"), std::string::npos);
    EXPECT_NE(text.find("trace y 0% (5/1000)", msg), std::string::npos) << "bar not redrawn after the message";
    EXPECT_NE(text.find("trace x 100% (4/4)"), std::string::npos) << text;
    EXPECT_NE(text.find("trace y 100% (1000/1000)"), std::string::npos) << text;
}

// What a loader warns about while a WarningCapture lives is collected once per message with its
// count, in order; info lines are not, and nothing is after it is gone.
TEST(WarningCapture, CollectsWarningsOnceEachWhileAlive) {
    std::FILE* out = std::tmpfile();
    ASSERT_NE(out, nullptr);
    initLogging(spdlog::level::info, out);
    std::vector<std::string> got;
    {
        WarningCapture capture;
        spdlog::warn("scene.obj:3: material 'light' not found");
        spdlog::info("loading");
        spdlog::warn("texture t.png: not found");
        spdlog::warn("scene.obj:3: material 'light' not found");
        spdlog::error("a failure");
        got = capture.take();
        EXPECT_TRUE(capture.take().empty());  // taken
    }
    spdlog::warn("after the capture");
    std::fclose(out);
    initLogging(spdlog::level::info);
    const std::vector<std::string> expected = {"scene.obj:3: material 'light' not found (2 times)",
                                               "texture t.png: not found", "a failure"};
    EXPECT_EQ(got, expected);
}

}  // namespace
}  // namespace aamap

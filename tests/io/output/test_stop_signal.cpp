// Stop signals: the handler records the first signal, a run loop's check throws with its name,
// and the watchdog ends a step that does not return, after writing its last word.

#include <csignal>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "io/output/stop_signal.hpp"

namespace ifsim::io {
namespace {

TEST(StopSignal, HandlerRecordsTheSignalAndTheCheckThrowsWithItsName) {
    const StopSignals installed;
    EXPECT_EQ(stop_signal(), 0);
    EXPECT_NO_THROW(throw_if_stopped("step 3 of 10", false));
    std::raise(SIGTERM); // handled: the test process goes on
    EXPECT_EQ(stop_signal(), SIGTERM);
    try {
        throw_if_stopped("step 3 of 10", true);
        FAIL() << "no RunInterrupted";
    } catch (const RunInterrupted& e) {
        EXPECT_EQ(e.signal(), SIGTERM);
        const std::string what = e.what();
        EXPECT_NE(what.find("interrupted by SIGTERM after step 3 of 10"), std::string::npos);
        EXPECT_NE(what.find("ifsim resume"), std::string::npos);
    }
    EXPECT_EQ(interrupted_exit_code(SIGTERM), 143);
}

// coreutils' `timeout` sends SIGTERM to the process and then to its process group: the two
// arrive together and are one stop, not the "second signal" that ends the process at once.
TEST(StopSignal, OneStopDeliveredTwiceIsOneStop) {
    const StopSignals installed;
    std::raise(SIGTERM);
    std::raise(SIGTERM); // without the delay rule: the default action, the test process ends
    EXPECT_EQ(stop_signal(), SIGTERM);
    EXPECT_THROW(throw_if_stopped("step 1 of 2", false), RunInterrupted);
}

// A repeat after the delay is a user who means it: the default action ends the process.
TEST(StopSignalDeathTest, SecondSignalAfterTheDelayEndsTheProcess) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_EXIT(
        {
            const StopSignals installed;
            std::raise(SIGINT);
            std::this_thread::sleep_for(std::chrono::nanoseconds(second_signal_delay_ns) +
                                        std::chrono::milliseconds(100));
            std::raise(SIGINT);
            std::exit(0); // not reached
        },
        testing::KilledBySignal(SIGINT), "");
}

TEST(StopSignal, NewInstallationForgetsAnEarlierRunsSignal) {
    {
        const StopSignals first;
        std::raise(SIGINT);
        EXPECT_EQ(stop_signal(), SIGINT);
    }
    const StopSignals second;
    EXPECT_EQ(stop_signal(), 0);
}

// A step that never returns after SIGTERM: the watchdog writes its last word and exits 143.
TEST(StopSignalDeathTest, WatchdogEndsAStuckStepAfterItsLastWord) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const auto marker = std::filesystem::temp_directory_path() / "ifsim-watchdog-last-word";
    std::filesystem::remove(marker);
    EXPECT_EXIT(
        {
            const StopSignals installed;
            StopWatchdog dog(std::chrono::milliseconds(100),
                             [&](int sig) { std::ofstream(marker) << signal_name(sig); });
            std::raise(SIGTERM);
            for (;;) { // the stuck step
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
            }
        },
        testing::ExitedWithCode(143), "");
    std::ifstream in(marker);
    std::string word;
    in >> word;
    EXPECT_EQ(word, "SIGTERM");
}

// A run that ends by itself disarms the watchdog: it never writes, also after a late signal.
TEST(StopSignal, DisarmedWatchdogStaysSilent) {
    const StopSignals installed;
    bool spoke = false;
    {
        StopWatchdog dog(std::chrono::milliseconds(1), [&](int) { spoke = true; });
        EXPECT_TRUE(dog.disarm());
        std::raise(SIGTERM);
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        EXPECT_FALSE(dog.disarm());
    }
    EXPECT_FALSE(spoke);
}

// An increment with checkpoints on may go on towards its checkpoint for the patience after
// the signal, counted from the first check that saw it, and no longer; the patience ends
// well inside the watchdog's grace, so the run's own ending still writes its files.
TEST(StopSignal, PatienceRunsFromTheFirstCheckThatSawTheSignal) {
    using namespace std::chrono_literals;
    static_assert(stop_patience < stop_grace);
    const StopSignals installed;
    StopPatience patience(5000ms);
    const auto t0 = StopPatience::Clock::time_point{} + 100s;
    EXPECT_FALSE(patience.exhausted(t0)); // no signal: never
    EXPECT_FALSE(patience.exhausted(t0 + 60s));
    std::raise(SIGTERM);
    const auto seen = t0 + 61s;
    EXPECT_FALSE(patience.exhausted(seen));
    EXPECT_FALSE(patience.exhausted(seen + 4999ms));
    EXPECT_TRUE(patience.exhausted(seen + 5000ms));
    EXPECT_TRUE(patience.exhausted(seen + 9s));
}

} // namespace
} // namespace ifsim::io

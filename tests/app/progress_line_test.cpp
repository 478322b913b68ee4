// The progress line's rate and ETA count from the start of the current stage, so that a curve's
// second pass is not estimated with the first pass's time.
#include "app/progress_line.h"

#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <sstream>
#include <string>

namespace fricrom::app {
namespace {

// Runs f with std::cerr captured; returns what it wrote.
template <class F>
std::string Captured(F f) {
  std::ostringstream out;
  std::streambuf* old = std::cerr.rdbuf(out.rdbuf());
  f();
  std::cerr.rdbuf(old);
  return out.str();
}

Progress Started100sAgo() {
  Progress p{true, "bounds"};
  p.terminal = true;  // every call writes (off a terminal at most one line per 10 s)
  p.t0 = std::chrono::steady_clock::now() - std::chrono::seconds(100);
  return p;
}

TEST(Progress, RateAndEtaRestartWithEachStage) {
  const Progress p = Started100sAgo();
  const std::string first = Captured([&] { p("frequencies", 5, 10); });
  EXPECT_NE(first.find("frequencies 5/10"), std::string::npos) << first;
  EXPECT_NE(first.find("ETA 100 s"), std::string::npos) << first;  // 5 units in 100 s
  // The second stage's first unit finished right after the first stage's last report: its rate
  // is not 1 per 100 s (which would give an ETA of 300 s).
  const std::string second = Captured([&] { p("neighbour starts", 1, 4); });
  EXPECT_NE(second.find("neighbour starts 1/4"), std::string::npos) << second;
  EXPECT_NE(second.find("ETA 0 s"), std::string::npos) << second;
}

TEST(Progress, SilentWhenDisabledAndNoEtaWhenDone) {
  Progress off = Started100sAgo();
  off.enabled = false;
  EXPECT_EQ(Captured([&] { off("frequencies", 1, 2); }), "");
  const Progress p = Started100sAgo();
  const std::string done = Captured([&] { p("frequencies", 2, 2); });
  EXPECT_NE(done.find("2/2"), std::string::npos) << done;
  EXPECT_EQ(done.find("ETA"), std::string::npos) << done;
}

}  // namespace
}  // namespace fricrom::app

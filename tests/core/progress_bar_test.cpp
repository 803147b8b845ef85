/// @file
/// @brief The tool's ProgressBar when stderr is not a terminal: plain lines at 10% steps, then "done".
#include "../../demos/cli/progress_bar.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

namespace {

TEST(ProgressBar, PrintsPlainStepLinesWhenStderrIsAFile) {
  const std::string path = ::testing::TempDir() + "sdfccd-progress-" + std::to_string(::getpid()) + ".txt";
  std::fflush(stderr);
  const int saved = ::dup(STDERR_FILENO);
  ASSERT_NE(std::freopen(path.c_str(), "w", stderr), nullptr);
  {
    sdfccd::cli::ProgressBar bar("work", 0.0);  // no delay: every step is due at once
    for (int n = 1; n <= 100; ++n) bar.update(n / 100.0);
  }
  std::fflush(stderr);
  ::dup2(saved, STDERR_FILENO);
  ::close(saved);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::remove(path.c_str());
  const std::string s = text.str();
  for (int p = 10; p <= 90; p += 10) {
    EXPECT_NE(s.find("work: " + std::to_string(p) + "% ("), std::string::npos) << s;
  }
  EXPECT_EQ(s.find("100%"), std::string::npos) << s;  // the end is the "done" line
  EXPECT_NE(s.find("work: done ("), std::string::npos) << s;
  EXPECT_EQ(s.find('\r'), std::string::npos) << "no redraws in a file: " << s;
}

}  // namespace

// Runs the built `sdcb` executable (SDCB_BINARY) and captures what it did.
#ifndef SDCB_TESTS_TESTING_RUN_SDCB_H_
#define SDCB_TESTS_TESTING_RUN_SDCB_H_

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "testing/temp_dir.h"

namespace sdcb::testing {

struct RunResult {
  int exit_code = -1;    // valid when !crashed
  bool crashed = false;  // killed by a signal (abort, segfault, ...)
  std::string out, err;
};

inline std::string ShellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') {
      q += "'\\''";
    } else {
      q += c;
    }
  }
  return q + "'";
}

// Runs `sdcb args...` with stdout and stderr captured into files in `dir`.
inline RunResult RunSdcb(const std::vector<std::string>& args,
                         const std::string& dir) {
  std::string command = ShellQuote(SDCB_BINARY);
  for (const auto& a : args) command += " " + ShellQuote(a);
  const std::string out = dir + "/.stdout", err = dir + "/.stderr";
  command += " >" + ShellQuote(out) + " 2>" + ShellQuote(err) + " </dev/null";
  const int status = std::system(command.c_str());
  RunResult r;
  if (WIFEXITED(status)) {
    r.exit_code = WEXITSTATUS(status);
    // The shell reports a child killed by signal N as exit 128 + N.
    r.crashed = r.exit_code >= 128;
  } else {
    r.crashed = true;
  }
  r.out = ReadBytes(out);
  r.err = ReadBytes(err);
  return r;
}

// What every failing command must print: one line on stderr naming `file`,
// and no crash.
inline void ExpectOneSentenceNaming(const RunResult& r,
                                    const std::string& file) {
  EXPECT_FALSE(r.crashed) << r.err;
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_RUN_SDCB_H_

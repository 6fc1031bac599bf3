// docs/CLI.md documents every option `sdcb --help` shows, and the usage
// shows every flag of core/fit/fit_options.h's FitOptionTable.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "sdcb/core/fit/fit_options.h"
#include "testing/run_sdcb.h"

namespace sdcb {
namespace {

using testing::FreshTestDir;
using testing::RunResult;
using testing::RunSdcb;

std::string Usage() {
  const std::string dir = FreshTestDir();
  const RunResult r = RunSdcb({"--help"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.out;
}

TEST(CliDocsTest, CliMdDocumentsEveryOptionOfTheUsage) {
  std::ifstream in(SDCB_SOURCE_DIR "/docs/CLI.md");
  std::ostringstream docs;
  docs << in.rdbuf();
  ASSERT_FALSE(docs.str().empty());
  const std::string usage = Usage();
  std::set<std::string> options;
  const std::regex option("--[a-z][a-z0-9-]*");
  for (auto it = std::sregex_iterator(usage.begin(), usage.end(), option);
       it != std::sregex_iterator(); ++it) {
    options.insert(it->str());
  }
  EXPECT_GT(options.size(), 40u);
  for (const std::string& name : options) {
    if (name == "--help") continue;
    // Anywhere in the text, not followed by more of a name.
    EXPECT_TRUE(
        std::regex_search(docs.str(), std::regex(name + "(?![a-z0-9-])")))
        << "docs/CLI.md lacks " << name;
  }
}

TEST(CliDocsTest, UsageShowsEveryFitFlagWithItsHelp) {
  const std::string usage = Usage();
  for (const FitOptionDescriptor& d : FitOptionTable()) {
    if (d.flag == nullptr) continue;
    std::string shown = "      --" + std::string(d.flag);
    if (d.value_name != nullptr) shown += " " + std::string(d.value_name);
    EXPECT_NE(usage.find(shown), std::string::npos) << shown;
  }
}

}  // namespace
}  // namespace sdcb

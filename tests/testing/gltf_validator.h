// The Khronos glTF validator (npm gltf-validator, run by
// scripts/gltf_tools/validate.js) on files the tests wrote: its report of
// each file, one JSON object per file with the counts of errors, warnings,
// infos and hints and the messages of errors and warnings.
#ifndef SDCB_TESTS_TESTING_GLTF_VALIDATOR_H_
#define SDCB_TESTS_TESTING_GLTF_VALIDATOR_H_

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "testing/run_sdcb.h"
#include "testing/temp_dir.h"

namespace sdcb::testing {

// The reports of `files`, in order (a line that is not JSON, such as
// node's own error, becomes {"errors": -1, "messages": [line]}), written
// through `dir`.
inline std::vector<nlohmann::json> ValidateGltf(
    const std::vector<std::string>& files, const std::string& dir) {
  std::string command = "node " + ShellQuote(std::string(SDCB_SOURCE_DIR) +
                                             "/scripts/gltf_tools/validate.js");
  for (const std::string& f : files) command += " " + ShellQuote(f);
  const std::string out = dir + "/validator.out";
  command += " > " + ShellQuote(out) + " 2>&1";
  (void)std::system(command.c_str());
  std::vector<nlohmann::json> reports;
  std::istringstream lines(ReadBytes(out));
  std::string line;
  while (std::getline(lines, line)) {
    nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object()) {
      j = {{"errors", -1}, {"messages", {line}}};
    }
    reports.push_back(std::move(j));
  }
  return reports;
}

}  // namespace sdcb::testing

#endif  // SDCB_TESTS_TESTING_GLTF_VALIDATOR_H_

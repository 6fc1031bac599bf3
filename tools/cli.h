// Shared pieces of the `sdcb` command line: argument parsing, exit codes,
// reporting of library statuses.
#ifndef SDCB_TOOLS_CLI_H_
#define SDCB_TOOLS_CLI_H_

#include <map>
#include <string>
#include <vector>

#include "sdcb/core/common/status.h"

namespace sdcb::cli {

// Exit codes of every subcommand (docs/CLI.md).
constexpr int kExitOk = 0;
constexpr int kExitBadInput = 1;  // unreadable / unusable input, failed write
constexpr int kExitUsage = 2;     // bad flags or arguments

// Thrown by the parser for a usage error; caught in main().
struct UsageError {
  std::string message;
};

// Parsed arguments: positionals in order, options by long name.
class Args {
 public:
  // `value_options` take a value ("--json FILE"); `flag_options` do not.
  Args(const std::vector<std::string>& argv,
       const std::vector<std::string>& value_options,
       const std::vector<std::string>& flag_options);

  const std::vector<std::string>& positionals() const { return positionals_; }
  bool Has(const std::string& name) const { return values_.count(name) > 0; }
  std::string Get(const std::string& name,
                  const std::string& fallback = "") const;
  double GetDouble(const std::string& name, double fallback, double lo,
                   double hi) const;
  int GetInt(const std::string& name, int fallback, int lo, int hi) const;
  // Exactly `n` positionals, else a UsageError naming `what`.
  void RequirePositionals(size_t n, const std::string& what) const;

 private:
  std::vector<std::string> positionals_;
  std::map<std::string, std::string> values_;
};

// Prints "sdcb: <message>" on stderr and returns kExitBadInput.
int ReportError(const Status& status);

// Writes `text` to `path` atomically, or to stdout when `path` is "-".
Status WriteTextOutput(const std::string& path, const std::string& text);

}  // namespace sdcb::cli

#endif  // SDCB_TOOLS_CLI_H_

// The subcommands of `sdcb`; each takes the arguments after its name and
// returns the process exit code (tools/cli.h).
#ifndef SDCB_TOOLS_COMMANDS_H_
#define SDCB_TOOLS_COMMANDS_H_

#include <string>
#include <vector>

namespace sdcb::cli {

// The options a command accepts: those that take a value ("--rmse 0.1")
// and flags ("--quiet"). `sdcb batch` routes a manifest row's options to
// `fit` or `export` by these lists.
struct CommandOptions {
  std::vector<std::string> values;
  std::vector<std::string> flags;
};
// One option of a command, as its usage text shows it: "--name VALUE" and
// its help sentence; `value` empty for a flag that takes none.
struct OptionSpec {
  std::string name;
  std::string value;
  std::string help;
};
// The names of `specs`, by whether they take a value.
CommandOptions OptionNamesOf(const std::vector<OptionSpec>& specs);
// One usage line per option: "      --name VALUE" then its help from column
// 30 on, wrapped within 79 columns.
std::string OptionUsage(const std::vector<OptionSpec>& specs);
// The options of `sdcb fit` (its FitOptions from core/fit/fit_options.h's
// FitOptionTable), and its usage text.
const std::vector<OptionSpec>& FitOptionSpecs();
std::string FitUsage();
const CommandOptions& FitOptionNames();
const CommandOptions& ExportOptionNames();
// The options of `sdcb export`, each once, with the outputs it applies to
// (the others refuse it): ExportOptionNames() comes from this list.
enum class ExportTarget { kAll, kMesh, kCad };
struct ExportOption {
  const char* name;
  bool takes_value;
  ExportTarget target;
};
const std::vector<ExportOption>& ExportOptions();
// Whether `export` writes files with this extension (lower case, with the
// dot: ".glb").
bool IsExportExtension(const std::string& extension);

int RunCheck(const std::vector<std::string>& args);
int RunParam(const std::vector<std::string>& args);
int RunFit(const std::vector<std::string>& args);
int RunInfo(const std::vector<std::string>& args);
int RunDump(const std::vector<std::string>& args);
int RunEval(const std::vector<std::string>& args);
int RunCompare(const std::vector<std::string>& args);
int RunExport(const std::vector<std::string>& args);
int RunBatch(const std::vector<std::string>& args);
int RunCage(const std::vector<std::string>& args);

class Args;
// `sdcb export` to STEP / IGES (tools/cad_export_command.cpp), called by
// RunExport for those extensions.
bool IsCadExtension(const std::string& ext);
int RunCadExport(const Args& args, const std::string& ext);

}  // namespace sdcb::cli

#endif  // SDCB_TOOLS_COMMANDS_H_

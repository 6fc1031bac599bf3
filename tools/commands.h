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
const CommandOptions& FitOptionNames();
const CommandOptions& ExportOptionNames();
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

// The `tessera` commands, one per file under src/cli/ (render.cpp, probe.cpp, list.cpp,
// options.cpp, info.cpp, report.cpp, diff.cpp, serve.cpp), each taking the arguments after its name and
// returning the exit code: 0 success, 1 failure while rendering, 2 bad usage or bad input
// (UsageError and InputError propagate to main.cpp, which prints them).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace tessera::cli {

int renderCommand(const std::vector<std::string_view>& args);
int probeCommand(const std::vector<std::string_view>& args);
int listCommand(const std::vector<std::string_view>& args);
int optionsCommand(const std::vector<std::string_view>& args);
int infoCommand(const std::vector<std::string_view>& args);
int reportCommand(const std::vector<std::string_view>& args);
int diffCommand(const std::vector<std::string_view>& args);
int serveCommand(const std::vector<std::string_view>& args);

// The command line as typed ("tessera render ..."), recorded in --dump's manifest; main sets it.
const std::string& commandLine();
void setCommandLine(std::string line);

} // namespace tessera::cli

// Runs a shell command from a test and captures its exit code and output.
#pragma once

#include <string>

namespace syn::testing {

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr, interleaved
};

// Runs `command` with /bin/sh, stderr merged into stdout.
CommandResult RunCommand(const std::string& command);

// Same, stdout only (stderr discarded), for tools whose stdout is data.
CommandResult RunCommandStdout(const std::string& command);

}  // namespace syn::testing

#include "tests/support/run_command.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>

namespace syn::testing {
namespace {

CommandResult Run(const std::string& full_command) {
  CommandResult result;
  FILE* pipe = popen(full_command.c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  size_t got = 0;
  while ((got = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.output.append(buffer.data(), got);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

}  // namespace

CommandResult RunCommand(const std::string& command) { return Run(command + " 2>&1"); }
CommandResult RunCommandStdout(const std::string& command) { return Run(command + " 2>/dev/null"); }

}  // namespace syn::testing

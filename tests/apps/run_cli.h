// Runs the inertia command for end-to-end tests; INERTIA_CLI is its path.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "../scratch_dir.h"

namespace inertia::test {

struct CliResult {
  int code = -1;
  std::string output;  // stdout and stderr together
};

/// Runs `[env] inertia args` through the shell; `env` is a prefix such as "PATH=/nowhere".
inline CliResult runCli(const std::string& args, const std::string& env = "") {
  const std::string command = env + (env.empty() ? "" : " ") + INERTIA_CLI + " " + args + " 2>&1";
  CliResult r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

/// A fresh temporary directory per test, removed afterwards; paths as strings for commands.
class CliTest : public ScratchDirTest {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    return ScratchDirTest::write(name, text).string();
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
};

}  // namespace inertia::test

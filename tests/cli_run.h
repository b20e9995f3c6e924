// Running the built `meshlift` executable from the tools tests.
#pragma once

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace meshlift::test {

struct CliRun {
  int exit_code;
  std::string output;  // stdout and stderr together
};

/// Runs `meshlift ARGS` (MESHLIFT_CLI is the built executable) and collects its output.
inline CliRun run_cli(const std::string& args) {
  const std::string command = std::string(MESHLIFT_CLI) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string output;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

/// A fresh directory under the system's temporary directory, unique to this process and `name`.
inline std::filesystem::path cli_scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("meshlift_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace meshlift::test

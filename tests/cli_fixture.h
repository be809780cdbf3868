// Runs the penumbra command (PENUMBRA_CLI, the built binary, or the environment's PENUMBRA_CLI: the
// bundle's, scripts/bundle.sh) the way a user does, in a fresh temporary folder per test, and
// captures its exit code, stdout and stderr.
#pragma once
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace penumbra::test {

struct CliResult {
  int exitCode;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("penumbra_cli_" + std::to_string(::getpid()) + "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  CliResult run(const std::string& args) const {
    const char* bundled = std::getenv("PENUMBRA_CLI");
    const std::string cmd = std::string(bundled && *bundled ? bundled : PENUMBRA_CLI) + " " + args + " > " +
                            (dir_ / "stdout").string() + " 2> " + (dir_ / "stderr").string();
    const int status = std::system(cmd.c_str());
    return {WEXITSTATUS(status), slurp(dir_ / "stdout"), slurp(dir_ / "stderr")};
  }
  std::filesystem::path dir_;
};

}  // namespace penumbra::test

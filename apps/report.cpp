#include "apps/report.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

namespace penumbra {

namespace fs = std::filesystem;

std::string reportScriptPath() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path beside = exe.parent_path() / "report" / "report.py";
    if (fs::is_regular_file(beside, ec)) return beside.string();
  }
  const fs::path source = fs::path(PENUMBRA_SOURCE_DIR) / "bench" / "report" / "report.py";
  if (fs::is_regular_file(source, ec)) return source.string();
  return {};
}

void writeReport(const std::string& kind, const std::string& dir) {
  const std::string script = reportScriptPath();
  if (script.empty()) {
    throw std::runtime_error("cannot write " + dir + "/report.html: report.py is neither beside the executable (report/) "
                             "nor in the source tree; rebuild, or pass --no-report");
  }
  const char* override = std::getenv("PENUMBRA_PYTHON");
  const std::string python = override && *override ? override : "/usr/bin/python3";
  // fork + exec with an argument vector: folder names reach the script untouched by a shell.
  std::vector<std::string> args{python, script, kind, dir};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(nullptr);  // our buffered output first, then the script's
  const pid_t child = fork();
  if (child < 0) throw std::runtime_error("cannot start " + python + " for the report");
  if (child == 0) {
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) throw std::runtime_error("lost the report process");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    throw std::runtime_error(
        code == 127 ? "cannot write " + dir + "/report.html: " + python +
                          " not found; run scripts/setup.sh (or set PENUMBRA_PYTHON), or pass --no-report"
                    : "cannot write " + dir + "/report.html: " + python + " " + script + " failed (exit " +
                          std::to_string(code) + ", see above); is python3-matplotlib installed (scripts/setup.sh)?");
  }
}

}  // namespace penumbra

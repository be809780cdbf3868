// The progress bar runSweep draws on stderr (apps/sweep.h: Sweep::progress).
#pragma once
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <iostream>
#include <sstream>
#include <string>

namespace penumbra {

// A progress bar on stderr, redrawn in place; silent when stderr is not a terminal (logs, tests).
class Progress {
 public:
  Progress(std::size_t total, bool wanted) : total_(total), enabled_(wanted && isatty(STDERR_FILENO)) {}
  ~Progress() {
    if (enabled_ && drawn_) std::cerr << "\r" << std::string(width_, ' ') << "\r" << std::flush;
  }
  void start(const std::string& what) {
    if (!enabled_) return;
    constexpr std::size_t kBar = 30;
    const std::size_t filled = total_ ? kBar * done_ / total_ : kBar;
    const auto elapsed = std::chrono::duration_cast<std::chrono::seconds>(std::chrono::steady_clock::now() - begin_);
    std::ostringstream line;
    line << "[" << std::string(filled, '#') << std::string(kBar - filled, '.') << "] " << done_ << "/" << total_ << "  "
         << elapsed.count() << " s  " << what;
    std::string text = line.str().substr(0, 110);
    width_ = std::max(width_, text.size());
    text.resize(width_, ' ');
    std::cerr << "\r" << text << std::flush;
    drawn_ = true;
    ++done_;
  }

 private:
  std::size_t total_, done_ = 0, width_ = 0;
  bool enabled_, drawn_ = false;
  std::chrono::steady_clock::time_point begin_ = std::chrono::steady_clock::now();
};

}  // namespace penumbra

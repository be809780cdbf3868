// The HTML report and its charts: bench/report/report.py (matplotlib) run on an output folder that
// compare, bench or tune has filled with images and JSON. The C++ side only finds and runs it.
#pragma once
#include <string>

namespace penumbra {

// report.py next to the executable (bin/report/report.py, copied there by the build), else the
// source tree's bench/report/report.py. Empty when neither exists.
std::string reportScriptPath();

// Runs `python3 report.py KIND DIR` (KIND: compare, bench or tune), which writes DIR/report.html
// and the charts. The interpreter is $PENUMBRA_PYTHON, else /usr/bin/python3 (Debian's, where
// scripts/setup.sh installs python3-matplotlib). Throws std::runtime_error saying what to install
// or fix when the script cannot run or fails.
void writeReport(const std::string& kind, const std::string& dir);

}  // namespace penumbra

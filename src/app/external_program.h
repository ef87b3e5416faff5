// Other programs meso runs (ffmpeg for --video, the plot scripts of trade and tables): found on
// $PATH and started with posix_spawn, without a shell.
#pragma once

#include <string>
#include <vector>

namespace meso::app {

// The full path of `program` from $PATH (regular and executable), or empty.
std::string findOnPath(const std::string& program);

// Runs argv[0] with the arguments as given (no shell: quotes, $(...) and ; in file names are just
// characters) and returns its exit status, -1 when it could not start or was killed.
int runProgram(const std::vector<std::string>& args);

// Debian's python3 (/usr/bin/python3: tools/install-deps installs matplotlib for it), else the
// python3 on $PATH, else empty.
std::string python();

// Runs `script` (a plot script in tools/) with python() and `args`; true when it ran and exited
// with status 0, false without python3 or the script, or when it failed (e.g. without matplotlib).
bool runPythonScript(const std::string& script, const std::vector<std::string>& args);

}  // namespace meso::app

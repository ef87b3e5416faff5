// Other programs meso runs (ffmpeg for --video, the trade plot script): found on $PATH and started
// with posix_spawn, without a shell.
#pragma once

#include <string>
#include <vector>

namespace meso::app {

// The full path of `program` from $PATH (regular and executable), or empty.
std::string findOnPath(const std::string& program);

// Runs argv[0] with the arguments as given (no shell: quotes, $(...) and ; in file names are just
// characters) and returns its exit status, -1 when it could not start or was killed.
int runProgram(const std::vector<std::string>& args);

}  // namespace meso::app

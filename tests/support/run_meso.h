// Runs the meso executable (MESO_EXE) with arguments, capturing stdout and stderr and the status.
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace meso::testing {

struct RunResult {
  int status = -1;     // exit status, -1 when killed by a signal
  std::string output;  // stdout and stderr
};

inline RunResult runMeso(const std::string& args) {
  const std::string cmd = std::string(MESO_EXE) + " " + args + " 2>&1";
  RunResult r;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int raw = pclose(p);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return r;
}

}  // namespace meso::testing

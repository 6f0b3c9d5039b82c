// Runs a shell command line (the CLI as a user types it) and gives back its exit status and
// stdout; stderr goes where the command line sends it (e.g. "2>&1", "2>FILE").
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace polyloc::test {

struct CommandRun {
  int rc = -1;      // exit status; -1 when it could not be started or did not exit
  std::string out;  // stdout
};

inline CommandRun runCommand(const std::string& command) {
  CommandRun r;
  FILE* p = ::popen(command.c_str(), "r");
  if (!p) return r;
  char buf[4096];
  for (size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;) r.out.append(buf, n);
  const int status = ::pclose(p);
  r.rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace polyloc::test

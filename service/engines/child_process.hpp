// A program started by polyloc (eval nav starts polylocd and the controller): posix_spawn with
// stdout/stderr into files, SIGTERM then SIGKILL on stop, reaped in the destructor so a failing
// evaluation leaves no process behind.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace polyloc::engines {

class ChildProcess {
 public:
  // Throws std::runtime_error naming the program when it cannot be started.
  ChildProcess(const std::vector<std::string>& argv, const std::string& stdout_path, const std::string& stderr_path);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool running();                      // false once it exited (reaped)
  int exitStatus() const { return status_; }  // as waitpid reports it (valid once not running)
  // SIGTERM, up to grace_s for it to end, then SIGKILL. Returns its exit code (128 + signal when killed).
  int stop(double grace_s = 5.0);
  // Waits up to timeout_s for it to end by itself; false when it is still running.
  bool wait(double timeout_s);
  const std::string& name() const { return name_; }

 private:
  pid_t pid_ = -1;
  int status_ = 0;
  std::string name_;
};

// The directory of this executable (/proc/self/exe): where polylocd and polynav lie beside it.
std::string executableDir();

}  // namespace polyloc::engines

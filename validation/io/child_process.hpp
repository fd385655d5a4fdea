#pragma once
// Runs a program with arguments (no shell), capturing its stdout and stderr together.
#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

namespace aggkit {

struct ProcessOutcome {
  bool started = false;
  bool timed_out = false;
  int exit_status = -1;  // the exit code, or -1 if it did not exit normally
  std::string output;    // stdout and stderr
  bool succeeded() const { return started && !timed_out && exit_status == 0; }
};

// argv[0] is looked up on PATH if it has no '/'. The child is killed after `timeout`.
ProcessOutcome run_process(const std::vector<std::string>& argv, std::chrono::seconds timeout);

// A program started ahead of its input, so that its start-up (an interpreter's imports) overlaps the
// caller's work: its stdin is a pipe that `finish` writes `input` to and closes, then it is waited for like
// run_process (the timeout counts from `finish`). A process never finished is killed and reaped by the
// destructor (also on exceptions); if the caller dies instead, the child reads end-of-file on its stdin.
class StartedProcess {
 public:
  explicit StartedProcess(const std::vector<std::string>& argv);
  ~StartedProcess();
  StartedProcess(const StartedProcess&) = delete;
  StartedProcess& operator=(const StartedProcess&) = delete;
  ProcessOutcome finish(const std::string& input, std::chrono::seconds timeout);  // once
  pid_t pid() const { return pid_; }  // -1 once finished or if it could not start

 private:
  pid_t pid_ = -1;
  int input_ = -1;   // the child's stdin (write end)
  int output_ = -1;  // the child's stdout and stderr (read end)
  std::string start_error_;
};

}  // namespace aggkit

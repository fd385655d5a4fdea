#pragma once
// Runs a program with arguments (no shell), capturing its stdout and stderr together.
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

}  // namespace aggkit

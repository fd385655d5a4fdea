#pragma once
// Runs programs as child processes, at most `parallel` at a time, each with its stdout and stderr in a log
// file. A child is sent SIGTERM if the process that started it dies (Linux PR_SET_PDEATHSIG), so that an
// interrupted validation leaves no scene running behind it. Call from a single-threaded process (fork).
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace aggkit {

struct ChildJob {
  std::vector<std::string> argv;  // argv[0]: the program's path
  std::filesystem::path log;      // stdout and stderr (created, truncated)
};

struct ChildOutcome {
  int exit_status = -1;  // the exit code, or -1 if it did not exit normally
  int signal = 0;        // the signal that ended it, if one did
  bool started = true;   // false: it could not be started (the log says why)
  double wall_seconds = 0;
};

struct JobCallbacks {
  std::function<void(std::size_t job)> started;
  std::function<void(std::size_t job, const ChildOutcome&)> finished;
  // Every `heartbeat` while jobs run: the jobs running and how long each has run.
  std::function<void(const std::vector<std::pair<std::size_t, double>>& running)> running;
  std::chrono::duration<double> heartbeat = std::chrono::seconds(30);
};

// Runs every job and returns when all have ended.
void run_child_jobs(const std::vector<ChildJob>& jobs, std::size_t parallel, const JobCallbacks& callbacks);

}  // namespace aggkit

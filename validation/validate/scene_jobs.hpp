#pragma once
// Runs programs as child processes on `slots` job slots (cores), each with its stdout and stderr in a log
// file: a job that can use several slots (ChildJob::max_slots > 1) is given the slots free when it starts
// and `spread` makes its command line for them; the jobs start in the order of job_slots.hpp (priority, then
// as given). A child is sent SIGTERM if the process that started it dies (Linux PR_SET_PDEATHSIG), so that an
// interrupted validation leaves no scene running behind it. Call from a single-threaded process (fork).
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace aggkit {

struct ChildJob {
  std::vector<std::string> argv;  // argv[0]: the program's path; the command on one slot
  std::filesystem::path log;      // stdout and stderr (created, truncated)
  std::size_t max_slots = 1;      // the most slots it can use
  int priority = 0;               // higher starts first
  // The command on `slots` > 1 slots (e.g. under mpiexec -np slots); only called when max_slots > 1.
  std::function<std::vector<std::string>(std::size_t slots)> spread;
  // "NAME=value" added to the environment of the spread command (a name already set is left as it is).
  std::vector<std::string> environment;
};

struct ChildOutcome {
  int exit_status = -1;  // the exit code, or -1 if it did not exit normally
  int signal = 0;        // the signal that ended it, if one did
  bool started = true;   // false: it could not be started (the log says why)
  double wall_seconds = 0;
};

struct RunningJob {
  std::size_t job = 0;
  double seconds = 0;     // how long it has run
  std::size_t slots = 1;  // the slots it holds
};

struct JobCallbacks {
  std::function<void(std::size_t job, std::size_t slots)> started;
  std::function<void(std::size_t job, const ChildOutcome&)> finished;
  // Every `heartbeat` while jobs run: the jobs running (in job order), how long each has run, its slots.
  std::function<void(const std::vector<RunningJob>& running)> running;
  std::chrono::duration<double> heartbeat = std::chrono::seconds(30);
};

// Runs every job and returns when all have ended.
void run_child_jobs(const std::vector<ChildJob>& jobs, std::size_t slots, const JobCallbacks& callbacks);

}  // namespace aggkit

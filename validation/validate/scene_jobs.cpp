#include "validation/validate/scene_jobs.hpp"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <map>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include "validation/validate/job_slots.hpp"

extern char** environ;

namespace aggkit {

namespace {

using Clock = std::chrono::steady_clock;

void write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n <= 0) return;
    done += std::size_t(n);
  }
}

// The parent's environment with `extra` ("NAME=value") added where NAME is not set.
std::vector<std::string> child_environment(const std::vector<std::string>& extra) {
  std::vector<std::string> environment;
  for (char** e = environ; e && *e; ++e) environment.emplace_back(*e);
  for (const auto& assignment : extra) {
    const std::string name = assignment.substr(0, assignment.find('='));
    if (!std::getenv(name.c_str())) environment.push_back(assignment);
  }
  return environment;
}

// fork + exec of `argv` with the log as stdout and stderr and /dev/null as stdin; -1 if fork failed.
pid_t start_child(const std::vector<std::string>& argv, const std::vector<std::string>& extra_environment,
                  const std::filesystem::path& log_file) {
  // Everything the child needs is prepared before fork: after it, only async-signal-safe calls.
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const std::vector<std::string> environment = child_environment(extra_environment);
  std::vector<char*> envp;
  for (const auto& e : environment) envp.push_back(const_cast<char*>(e.c_str()));
  envp.push_back(nullptr);
  const std::string log = log_file.string();
  const std::string cannot = "aggkit validate: cannot start " + argv.front() + ": ";
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent) ::_exit(127);  // the parent died before prctl
  // A new file, not the old one truncated: a process left from an earlier, killed validation (a scan's MPI
  // daemon reporting its parent's end) may still hold the old log open and would write into this one.
  ::unlink(log.c_str());
  const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int in = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (out < 0 || in < 0) ::_exit(127);
  ::dup2(in, STDIN_FILENO);
  ::dup2(out, STDOUT_FILENO);
  ::dup2(out, STDERR_FILENO);
  ::execve(args[0], args.data(), envp.data());
  write_all(STDERR_FILENO, cannot + std::strerror(errno) + "\n");
  ::_exit(127);
}

struct Child {
  std::size_t job = 0;
  Clock::time_point start;
};

// Starts every job the scheduler lets start now.
void start_jobs(const std::vector<ChildJob>& jobs, SlotScheduler& scheduler, std::map<pid_t, Child>& running,
                const JobCallbacks& callbacks) {
  while (const auto start = scheduler.next()) {
    const ChildJob& job = jobs[start->job];
    const auto now = Clock::now();
    const bool spread = start->slots > 1 && job.spread;
    const pid_t pid = spread ? start_child(job.spread(start->slots), job.environment, job.log)
                             : start_child(job.argv, {}, job.log);
    if (pid < 0) {
      scheduler.finished(start->job);
      ChildOutcome outcome;
      outcome.started = false;
      if (callbacks.finished) callbacks.finished(start->job, outcome);
    } else {
      running[pid] = {start->job, now};
      if (callbacks.started) callbacks.started(start->job, start->slots);
    }
  }
}

void report_running(const std::map<pid_t, Child>& running, const SlotScheduler& scheduler,
                    const JobCallbacks& callbacks) {
  std::vector<RunningJob> now;
  for (const auto& [pid, child] : running)
    now.push_back({child.job, std::chrono::duration<double>(Clock::now() - child.start).count(),
                   scheduler.held_by(child.job)});
  std::sort(now.begin(), now.end(), [](const RunningJob& x, const RunningJob& y) { return x.job < y.job; });
  callbacks.running(now);
}

}  // namespace

void run_child_jobs(const std::vector<ChildJob>& jobs, std::size_t slots, const JobCallbacks& callbacks) {
  std::vector<SlotDemand> demands;
  for (const auto& job : jobs) demands.push_back({job.spread ? job.max_slots : 1, job.priority});
  SlotScheduler scheduler(std::move(demands), slots);
  std::map<pid_t, Child> running;
  auto last_heartbeat = Clock::now();
  const auto ended = [&](const Child& child, const ChildOutcome& outcome) {
    scheduler.finished(child.job);
    if (callbacks.finished) callbacks.finished(child.job, outcome);
  };
  while (!scheduler.all_started() || !running.empty()) {
    start_jobs(jobs, scheduler, running, callbacks);
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, WNOHANG);
    if (pid > 0) {
      const auto it = running.find(pid);
      if (it == running.end()) continue;  // not one of ours
      ChildOutcome outcome;
      outcome.wall_seconds = std::chrono::duration<double>(Clock::now() - it->second.start).count();
      if (WIFEXITED(status)) outcome.exit_status = WEXITSTATUS(status);
      if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
      const Child child = it->second;
      running.erase(it);
      ended(child, outcome);
      continue;
    }
    if (pid < 0 && errno == ECHILD) {  // our children are gone without a status (reaped elsewhere)
      const auto gone = running;
      running.clear();
      for (const auto& [child_pid, child] : gone) {
        ChildOutcome outcome;
        outcome.wall_seconds = std::chrono::duration<double>(Clock::now() - child.start).count();
        ended(child, outcome);
      }
      continue;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (callbacks.running && !running.empty() && Clock::now() - last_heartbeat >= callbacks.heartbeat) {
      last_heartbeat = Clock::now();
      report_running(running, scheduler, callbacks);
    }
  }
}

}  // namespace aggkit

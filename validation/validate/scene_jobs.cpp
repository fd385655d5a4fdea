#include "validation/validate/scene_jobs.hpp"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <map>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

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

// fork + exec with the log as stdout and stderr and /dev/null as stdin; -1 if fork failed.
pid_t start_child(const ChildJob& job) {
  // Everything the child needs is prepared before fork: after it, only async-signal-safe calls.
  std::vector<char*> args;
  for (const auto& a : job.argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const std::string log = job.log.string();
  const std::string cannot = "aggkit validate: cannot start " + job.argv.front() + ": ";
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent) ::_exit(127);  // the parent died before prctl
  const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int in = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (out < 0 || in < 0) ::_exit(127);
  ::dup2(in, STDIN_FILENO);
  ::dup2(out, STDOUT_FILENO);
  ::dup2(out, STDERR_FILENO);
  ::execv(args[0], args.data());
  write_all(STDERR_FILENO, cannot + std::strerror(errno) + "\n");
  ::_exit(127);
}

}  // namespace

void run_child_jobs(const std::vector<ChildJob>& jobs, std::size_t parallel, const JobCallbacks& callbacks) {
  parallel = std::max<std::size_t>(parallel, 1);
  std::map<pid_t, std::pair<std::size_t, Clock::time_point>> running;  // pid -> (job, start)
  std::size_t next = 0;
  auto last_heartbeat = Clock::now();
  while (next < jobs.size() || !running.empty()) {
    while (next < jobs.size() && running.size() < parallel) {
      const auto start = Clock::now();
      const pid_t pid = start_child(jobs[next]);
      if (pid < 0) {
        ChildOutcome outcome;
        outcome.started = false;
        if (callbacks.finished) callbacks.finished(next, outcome);
      } else {
        running[pid] = {next, start};
        if (callbacks.started) callbacks.started(next);
      }
      ++next;
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, WNOHANG);
    if (pid > 0) {
      const auto it = running.find(pid);
      if (it == running.end()) continue;  // not one of ours
      ChildOutcome outcome;
      outcome.wall_seconds = std::chrono::duration<double>(Clock::now() - it->second.second).count();
      if (WIFEXITED(status)) outcome.exit_status = WEXITSTATUS(status);
      if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
      const std::size_t job = it->second.first;
      running.erase(it);
      if (callbacks.finished) callbacks.finished(job, outcome);
      continue;
    }
    if (pid < 0 && errno == ECHILD) {  // our children are gone without a status (reaped elsewhere)
      for (const auto& [child, job] : running) {
        ChildOutcome outcome;
        outcome.wall_seconds = std::chrono::duration<double>(Clock::now() - job.second).count();
        if (callbacks.finished) callbacks.finished(job.first, outcome);
      }
      running.clear();
      continue;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (callbacks.running && !running.empty() && Clock::now() - last_heartbeat >= callbacks.heartbeat) {
      last_heartbeat = Clock::now();
      std::vector<std::pair<std::size_t, double>> now;
      for (const auto& [child, job] : running)
        now.emplace_back(job.first, std::chrono::duration<double>(last_heartbeat - job.second).count());
      std::sort(now.begin(), now.end());
      callbacks.running(now);
    }
  }
}

}  // namespace aggkit

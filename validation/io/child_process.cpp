#include "validation/io/child_process.hpp"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace aggkit {

namespace {

struct Spawned {
  pid_t pid = -1;
  int input = -1;   // write end of the child's stdin pipe (with_input), else -1
  int output = -1;  // read end of the child's stdout/stderr
  std::string error;
};

// Starts argv with stdout and stderr into one pipe; stdin a pipe (with_input) or /dev/null. Every pipe end
// the parent keeps is close-on-exec, so no other child inherits it (an inherited stdin write end would keep
// a started process from ever seeing end-of-file).
Spawned spawn(const std::vector<std::string>& argv, bool with_input) {
  Spawned s;
  int out[2];
  if (::pipe2(out, O_CLOEXEC) != 0) {
    s.error = std::string("pipe: ") + std::strerror(errno);
    return s;
  }
  int in[2] = {-1, -1};
  if (with_input && ::pipe2(in, O_CLOEXEC) != 0) {
    s.error = std::string("pipe: ") + std::strerror(errno);
    ::close(out[0]);
    ::close(out[1]);
    return s;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDERR_FILENO);
  if (with_input) posix_spawn_file_actions_adddup2(&actions, in[0], STDIN_FILENO);
  else posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);

  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const int spawned = posix_spawnp(&s.pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(out[1]);
  if (with_input) ::close(in[0]);
  if (spawned != 0) {
    ::close(out[0]);
    if (with_input) ::close(in[1]);
    s.pid = -1;
    s.error = "cannot start " + argv[0] + ": " + std::strerror(spawned);
    return s;
  }
  s.output = out[0];
  s.input = with_input ? in[1] : -1;
  return s;
}

// Reads the child's output until end-of-file or the deadline (then kills it), closes it and reaps the child.
void collect(pid_t pid, int output, std::chrono::seconds timeout, ProcessOutcome& outcome) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  char buffer[4096];
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      outcome.timed_out = true;
      ::kill(pid, SIGKILL);
      break;
    }
    pollfd fd{output, POLLIN, 0};
    const int ready = ::poll(&fd, 1, int(left.count()));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;  // the deadline check above ends the loop
    const ssize_t got = ::read(output, buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;  // EOF: the child closed its output
    outcome.output.append(buffer, std::size_t(got));
  }
  ::close(output);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!outcome.timed_out && WIFEXITED(status)) outcome.exit_status = WEXITSTATUS(status);
}

// Writes all of `text` to `fd` without dying of SIGPIPE if the reader has gone (a child that exited early):
// SIGPIPE is blocked in this thread for the write and a pending one is consumed. False if the write failed.
bool write_all(int fd, const std::string& text) {
  sigset_t pipe_signal, previous;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_signal, &previous);
  std::size_t done = 0;
  bool ok = true;
  while (done < text.size()) {
    const ssize_t wrote = ::write(fd, text.data() + done, text.size() - done);
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote <= 0) {
      ok = false;
      break;
    }
    done += std::size_t(wrote);
  }
  if (!ok && errno == EPIPE && !sigismember(&previous, SIGPIPE)) {
    const timespec now{0, 0};
    while (sigtimedwait(&pipe_signal, nullptr, &now) < 0 && errno == EINTR) {
    }
  }
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  return ok;
}

}  // namespace

ProcessOutcome run_process(const std::vector<std::string>& argv, std::chrono::seconds timeout) {
  ProcessOutcome outcome;
  const Spawned s = spawn(argv, false);
  if (s.pid < 0) {
    outcome.output = s.error;
    return outcome;
  }
  outcome.started = true;
  collect(s.pid, s.output, timeout, outcome);
  return outcome;
}

StartedProcess::StartedProcess(const std::vector<std::string>& argv) {
  const Spawned s = spawn(argv, true);
  pid_ = s.pid;
  input_ = s.input;
  output_ = s.output;
  start_error_ = s.error;
}

StartedProcess::~StartedProcess() {
  if (pid_ < 0) return;
  ::close(input_);
  ::kill(pid_, SIGKILL);
  ::close(output_);
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
}

ProcessOutcome StartedProcess::finish(const std::string& input, std::chrono::seconds timeout) {
  ProcessOutcome outcome;
  if (pid_ < 0) {
    outcome.output = start_error_.empty() ? "the process was already finished" : start_error_;
    return outcome;
  }
  outcome.started = true;
  write_all(input_, input);  // a child that exited early has its say in its output and exit status
  ::close(input_);
  collect(pid_, output_, timeout, outcome);
  pid_ = -1;
  return outcome;
}

}  // namespace aggkit

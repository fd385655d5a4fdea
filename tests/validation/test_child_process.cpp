// A process started ahead of its input (the plotter's interpreter, started before the engines run): it gets
// its input, is never left behind, and a child that is gone does not take the caller down with SIGPIPE.
#include <catch2/catch.hpp>

#include <csignal>
#include <cerrno>
#include <sys/types.h>
#include <signal.h>

#include "validation/io/child_process.hpp"
#include "validation/io/python_plotter.hpp"
#include "tests/validation/scene_fixture.hpp"

using namespace aggkit;

TEST_CASE("child process: a started process reads its input when finished") {
  StartedProcess cat({"cat"});
  REQUIRE(cat.pid() > 0);
  const ProcessOutcome outcome = cat.finish(std::string("one\0two\n", 8), std::chrono::seconds(30));
  CHECK(outcome.succeeded());
  CHECK(outcome.output == std::string("one\0two\n", 8));
  CHECK(cat.pid() == -1);
}

TEST_CASE("child process: a started process never finished is killed and reaped") {
  pid_t pid = -1;
  {
    StartedProcess sleeper({"sleep", "100"});
    pid = sleeper.pid();
    REQUIRE(pid > 0);
    CHECK(::kill(pid, 0) == 0);  // running
  }
  // Reaped, not a zombie: the pid no longer exists (a zombie still answers kill(pid, 0)).
  CHECK(::kill(pid, 0) == -1);
  CHECK(errno == ESRCH);
}

TEST_CASE("child process: input to a child that already exited is no SIGPIPE") {
  StartedProcess quitter({"true"});
  REQUIRE(quitter.pid() > 0);
  const std::string big(1 << 20, 'x');  // more than a pipe holds: the write meets the closed reader
  const ProcessOutcome outcome = quitter.finish(big, std::chrono::seconds(30));
  CHECK(outcome.started);
  CHECK(outcome.exit_status == 0);
}

TEST_CASE("child process: a program that cannot start says so when finished") {
  StartedProcess missing({"/nonexistent/program"});
  CHECK(missing.pid() == -1);
  const ProcessOutcome outcome = missing.finish("x", std::chrono::seconds(30));
  CHECK_FALSE(outcome.started);
  CHECK_THAT(outcome.output, Catch::Contains("cannot start /nonexistent/program"));
}

TEST_CASE("child process: the started plot command runs a script with the arguments it is sent") {
  const auto folder = aggkit::testing::scratch_folder("started-plot");
  const auto script = aggkit::testing::write_text(folder / "echo_args.py",
                                                  "import sys\nprint('|'.join(sys.argv[1:]))\nprint(sys.path[0])\n");
  StartedProcess python(started_plot_command(script));
  REQUIRE(python.pid() > 0);
  const ProcessOutcome outcome =
      python.finish(started_plot_input({"--output", "a b.png", "--title=-x", ""}), std::chrono::seconds(60));
  CHECK(outcome.succeeded());
  CHECK_THAT(outcome.output, Catch::Contains("--output|a b.png|--title=-x|\n" + std::filesystem::absolute(folder).string() + "\n"));
  // Stdin closed with no arguments (the run ended without plotting): a silent, successful exit.
  StartedProcess idle(started_plot_command(script));
  const ProcessOutcome nothing = idle.finish("", std::chrono::seconds(60));
  CHECK(nothing.succeeded());
  CHECK(nothing.output.empty());
}

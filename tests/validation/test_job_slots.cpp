// The job slots of `aggkit validate --jobs K`: which scene starts next, how many cores (slots) it holds, and
// that the child processes are started with the command line and environment for the slots they hold.
#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <random>
#include <stdexcept>

#include "tests/validation/scene_fixture.hpp"
#include "validation/validate/job_slots.hpp"
#include "validation/validate/scene_jobs.hpp"

using namespace aggkit;

namespace {

SlotScheduler::Start start(SlotScheduler& scheduler) {
  const auto s = scheduler.next();
  REQUIRE(s.has_value());
  return *s;
}

}  // namespace

TEST_CASE("job slots: the scan starts first on every free slot, then the full tier, then the fast, one slot each") {
  // A run scene (fast), a run scene (full), a scan of 10 points, another fast run scene; 2 slots.
  SlotScheduler scheduler({{1, 0}, {1, 1}, {10, 2}, {1, 0}}, 2);
  auto s = start(scheduler);
  CHECK(s.job == 2);
  CHECK(s.slots == 2);
  CHECK(scheduler.free_slots() == 0);
  CHECK_FALSE(scheduler.next());  // nothing starts while the scan holds both slots
  scheduler.finished(2);
  CHECK(scheduler.free_slots() == 2);
  CHECK(scheduler.held_by(2) == 0);
  s = start(scheduler);
  CHECK((s.job == 1 && s.slots == 1));
  s = start(scheduler);
  CHECK((s.job == 0 && s.slots == 1));  // ties keep the order given
  CHECK_FALSE(scheduler.next());
  CHECK_FALSE(scheduler.all_started());
  scheduler.finished(1);
  s = start(scheduler);
  CHECK((s.job == 3 && s.slots == 1));
  CHECK(scheduler.all_started());
  CHECK_FALSE(scheduler.next());
  CHECK_THROWS_AS(scheduler.finished(1), std::logic_error);  // its slot was given back already
}

TEST_CASE("job slots: a spreading job takes what is free, at most what it can use") {
  SlotScheduler scheduler({{1, 3}, {2, 2}, {8, 2}, {1, 0}}, 4);
  auto s = start(scheduler);
  CHECK((s.job == 0 && s.slots == 1));
  s = start(scheduler);
  CHECK((s.job == 1 && s.slots == 2));  // 3 free, it can use 2
  s = start(scheduler);
  CHECK((s.job == 2 && s.slots == 1));  // the one left
  CHECK_FALSE(scheduler.next());
  scheduler.finished(1);
  s = start(scheduler);
  CHECK((s.job == 3 && s.slots == 1));
  CHECK(scheduler.free_slots() == 1);
  // One slot whatever is asked: at least one slot a job, and --jobs 1 runs a scan on one.
  SlotScheduler one({{0, 0}, {5, 1}}, 1);
  s = start(one);
  CHECK((s.job == 1 && s.slots == 1));
}

TEST_CASE("job slots: over random runs no slot is lost, none is double-booked and none idles while a job waits") {
  std::mt19937 random(12345);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t slots = 1 + random() % 6, count = random() % 12;
    std::vector<SlotDemand> jobs;
    for (std::size_t j = 0; j < count; ++j) jobs.push_back({1 + random() % 8, int(random() % 3)});
    SlotScheduler scheduler(jobs, slots);
    std::vector<std::size_t> running, order;
    while (!scheduler.all_started() || !running.empty()) {
      while (const auto s = scheduler.next()) {
        CHECK(s->slots >= 1);
        CHECK(s->slots <= jobs[s->job].max_slots);
        running.push_back(s->job);
        order.push_back(s->job);
      }
      std::size_t held = 0;
      for (const std::size_t job : running) held += scheduler.held_by(job);
      REQUIRE(held + scheduler.free_slots() == slots);
      if (!scheduler.all_started()) REQUIRE(scheduler.free_slots() == 0);  // a job waits only for a slot
      REQUIRE_FALSE(running.empty());
      const std::size_t k = random() % running.size();
      scheduler.finished(running[k]);
      running.erase(running.begin() + std::ptrdiff_t(k));
    }
    REQUIRE(scheduler.free_slots() == slots);
    REQUIRE(order.size() == count);
    for (std::size_t k = 1; k < order.size(); ++k) CHECK(jobs[order[k - 1]].priority >= jobs[order[k]].priority);
  }
}

TEST_CASE("job slots: a child on several slots runs its spread command line with its environment") {
  const auto folder = aggkit::testing::scratch_folder("job-slots-children");
  const auto job = [&](const std::string& name, std::size_t max_slots, int priority) {
    ChildJob j;
    j.argv = {"/bin/sh", "-c", "echo one slot $AGGKIT_TEST_SLOTS_VARIABLE"};
    j.log = folder / (name + ".log");
    j.max_slots = max_slots;
    j.priority = priority;
    if (max_slots > 1) {
      j.spread = [](std::size_t slots) {
        return std::vector<std::string>{"/bin/sh", "-c", "echo " + std::to_string(slots) + " slots $AGGKIT_TEST_SLOTS_VARIABLE"};
      };
      j.environment = {"AGGKIT_TEST_SLOTS_VARIABLE=set"};
    }
    return j;
  };
  const std::vector<ChildJob> jobs{job("run", 1, 0), job("scan", 5, 2), job("small-scan", 3, 1)};
  std::vector<std::pair<std::size_t, std::size_t>> started;
  std::vector<std::size_t> finished;
  JobCallbacks callbacks;
  callbacks.started = [&](std::size_t j, std::size_t slots) { started.emplace_back(j, slots); };
  callbacks.finished = [&](std::size_t j, const ChildOutcome& outcome) {
    CHECK(outcome.exit_status == 0);
    finished.push_back(j);
  };
  run_child_jobs(jobs, 3, callbacks);
  // The scan first, on all 3 slots; the small scan when they are free again, on all 3; then the run scene.
  REQUIRE(started.size() == 3);
  CHECK(started[0] == std::make_pair(std::size_t(1), std::size_t(3)));
  CHECK(started[1] == std::make_pair(std::size_t(2), std::size_t(3)));
  CHECK(started[2] == std::make_pair(std::size_t(0), std::size_t(1)));
  CHECK(finished == std::vector<std::size_t>{1, 2, 0});
  CHECK(aggkit::testing::read_text(folder / "scan.log") == "3 slots set\n");
  CHECK(aggkit::testing::read_text(folder / "small-scan.log") == "3 slots set\n");
  CHECK(aggkit::testing::read_text(folder / "run.log") == "one slot\n");  // no spread, no added environment
  // A spreading job given one slot runs its one-slot command line, without the added environment.
  std::vector<ChildJob> narrow{job("narrow", 4, 0)};
  started.clear();
  finished.clear();
  run_child_jobs(narrow, 1, callbacks);
  CHECK(started == std::vector<std::pair<std::size_t, std::size_t>>{{0, 1}});
  CHECK(aggkit::testing::read_text(folder / "narrow.log") == "one slot\n");
}

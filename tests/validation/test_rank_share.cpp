// Realizations over ranks (validation/engines/rank_share.hpp) on ranks played by threads of this process:
// which realizations each rank runs, rank 0 receiving every result in realization order, idle ranks, and a
// failure on any rank failing the share on every rank (rank 0 throws it with the rank named, the others end
// quietly) instead of leaving a rank waiting.
#include <catch2/catch.hpp>

#include <barrier>
#include <exception>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "analysis/input_error.hpp"
#include "validation/engines/rank_share.hpp"

using aggkit::RankGroup;

namespace {

// K ranks as K threads: gather and broadcast meet at a barrier, as every MPI rank meets in a collective.
struct Meeting {
  explicit Meeting(int size) : sync(size), slots(std::size_t(size)) {}
  std::barrier<> sync;
  std::vector<std::string> slots;
  std::string message;
};

class ThreadRank final : public RankGroup {
 public:
  ThreadRank(Meeting& meeting, int rank) : meeting_(meeting), rank_(rank) {}
  int rank() const override { return rank_; }
  int size() const override { return int(meeting_.slots.size()); }
  std::vector<std::string> gather(const std::string& mine) const override {
    meeting_.slots[std::size_t(rank_)] = mine;
    meeting_.sync.arrive_and_wait();
    std::vector<std::string> all = rank_ == 0 ? meeting_.slots : std::vector<std::string>{};
    meeting_.sync.arrive_and_wait();
    return all;
  }
  std::string broadcast(const std::string& message) const override {
    if (rank_ == 0) meeting_.message = message;
    meeting_.sync.arrive_and_wait();
    std::string received = meeting_.message;
    meeting_.sync.arrive_and_wait();
    return received;
  }

 private:
  Meeting& meeting_;
  int rank_;
};

// Runs `body(rank)` on `size` threads, each a rank; what each threw (null: nothing).
std::vector<std::exception_ptr> on_ranks(int size, const std::function<void(const RankGroup&)>& body) {
  Meeting meeting(size);
  std::vector<std::exception_ptr> thrown(static_cast<std::size_t>(size));
  std::vector<std::thread> threads;
  for (int k = 0; k < size; ++k)
    threads.emplace_back([&, k] {
      const ThreadRank rank(meeting, k);
      try {
        body(rank);
      } catch (...) {
        thrown[std::size_t(k)] = std::current_exception();
      }
    });
  for (auto& thread : threads) thread.join();
  return thrown;
}

bool abandoned(const std::exception_ptr& e, bool input) {
  try {
    std::rethrow_exception(e);
  } catch (const aggkit::ShareAbandoned& a) {
    return a.input == input;
  } catch (...) {
    return false;
  }
}

}  // namespace

TEST_CASE("rank share: rank k runs k, k + K, ..., rank 0 gets every result in realization order, idle ranks") {
  for (const auto& [ranks_given, count_given] : {std::pair{3, 7}, std::pair{4, 2}, std::pair{2, 1}}) {
    const int ranks = ranks_given, count = count_given;  // plain variables: clang 14 cannot capture bindings
    INFO(ranks << " ranks, " << count << " realizations");
    std::vector<std::vector<std::string>> received(static_cast<std::size_t>(ranks));
    std::vector<std::vector<std::size_t>> ran(static_cast<std::size_t>(ranks));
    const auto thrown = on_ranks(ranks, [&](const RankGroup& group) {
      received[std::size_t(group.rank())] =
          aggkit::gather_realizations(&group, std::size_t(count), [&](const std::vector<std::size_t>& mine) {
            ran[std::size_t(group.rank())] = mine;
            std::vector<std::string> results;
            for (std::size_t r : mine) results.push_back("realization " + std::to_string(r));
            return results;
          });
    });
    for (const auto& e : thrown) CHECK_FALSE(e);
    REQUIRE(received[0].size() == std::size_t(count));
    for (int r = 0; r < count; ++r) CHECK(received[0][std::size_t(r)] == "realization " + std::to_string(r));
    std::size_t total = 0;
    for (int k = 0; k < ranks; ++k) {
      if (k > 0) CHECK(received[std::size_t(k)].empty());
      std::vector<std::size_t> expected;  // k, k + K, ...
      for (int r = k; r < count; r += ranks) expected.push_back(std::size_t(r));
      CHECK(ran[std::size_t(k)] == expected);
      total += ran[std::size_t(k)].size();
    }
    CHECK(total == std::size_t(count));  // each realization once
    if (ranks > count) CHECK(ran.back().empty());  // an idle rank
  }
  // One process: every realization here, no ranks involved.
  CHECK(aggkit::realizations_of_rank(3, nullptr) == std::vector<std::size_t>{0, 1, 2});
  CHECK(aggkit::gather_shares(nullptr, [] { return std::string("alone"); }) == std::vector<std::string>{"alone"});
}

TEST_CASE("rank share: a failure on one rank fails the share on every rank, rank 0 naming the rank") {
  SECTION("bad input on rank 1: rank 0 throws it with its key, the others end quietly") {
    const auto thrown = on_ranks(3, [](const RankGroup& group) {
      aggkit::gather_shares(&group, [&]() -> std::string {
        if (group.rank() == 1) throw aggkit::InputError("engine[0].runs", "-3", "an integer from 1 to 1e6");
        return "fine";
      });
    });
    REQUIRE(thrown[0]);
    try {
      std::rethrow_exception(thrown[0]);
    } catch (const aggkit::InputError& e) {
      CHECK(e.key() == "engine[0].runs");
      CHECK(std::string(e.what()) == "engine[0].runs = -3: an integer from 1 to 1e6 (on MPI rank 1)");
    }
    CHECK(abandoned(thrown[1], true));
    CHECK(abandoned(thrown[2], true));
  }
  SECTION("a failed run on rank 2 and on rank 0: rank 0 throws its own") {
    const auto thrown = on_ranks(3, [](const RankGroup& group) {
      aggkit::gather_shares(&group, [&]() -> std::string {
        if (group.rank() != 1) throw std::runtime_error("budget spent on rank " + std::to_string(group.rank()));
        return "fine";
      });
    });
    REQUIRE(thrown[0]);
    CHECK_THROWS_WITH(std::rethrow_exception(thrown[0]), "budget spent on rank 0");
    CHECK(abandoned(thrown[1], false));
    CHECK(abandoned(thrown[2], false));
  }
  SECTION("a failed run on rank 2 only") {
    const auto thrown = on_ranks(3, [](const RankGroup& group) {
      aggkit::gather_realizations(&group, 5, [&](const std::vector<std::size_t>& mine) {
        if (group.rank() == 2) throw std::runtime_error("stopped: the wall-time budget ran out");
        return std::vector<std::string>(mine.size(), "x");
      });
    });
    REQUIRE(thrown[0]);
    CHECK_THROWS_WITH(std::rethrow_exception(thrown[0]), "stopped: the wall-time budget ran out (on MPI rank 2)");
    CHECK(abandoned(thrown[1], false));
    CHECK(abandoned(thrown[2], false));
  }
}

#include "validation/engines/rank_share.hpp"

#include <cstdint>
#include <exception>
#include <stdexcept>

#include "analysis/input_error.hpp"

namespace aggkit {

namespace {

// A rank's part of a share: its outcome, then its result or its failure.
enum class Outcome : std::uint8_t { done = 0, bad_input = 1, failed = 2 };

std::string failure_payload(Outcome outcome, const std::string& key, const std::string& message) {
  StateWriter out;
  out.put(outcome);
  out.put(key);
  out.put(message);
  return out.take();
}

// The failure a rank sent, thrown again on rank 0 with the rank named.
[[noreturn]] void throw_failure(const std::string& payload, int rank) {
  StateReader in(payload);
  const Outcome outcome = in.read<Outcome>();
  std::string key, message;
  in.get(key);
  in.get(message);
  const std::string where = " (on MPI rank " + std::to_string(rank) + ")";
  if (outcome == Outcome::bad_input) {
    // InputError's words are "key = value: allowed"; split back so the message reads the same.
    const std::string rest = message.rfind(key + " = ", 0) == 0 ? message.substr(key.size() + 3) : message;
    const std::size_t colon = rest.find(": ");
    if (colon == std::string::npos) throw InputError(key, rest, "(see above)" + where);
    throw InputError(key, rest.substr(0, colon), rest.substr(colon + 2) + where);
  }
  throw std::runtime_error(message + where);
}

}  // namespace

const RankGroup* shared_ranks(const RankGroup* ranks) { return ranks && ranks->size() > 1 ? ranks : nullptr; }

std::vector<std::size_t> realizations_of_rank(std::size_t count, const RankGroup* ranks) {
  const std::size_t rank = ranks ? std::size_t(ranks->rank()) : 0, size = ranks ? std::size_t(ranks->size()) : 1;
  std::vector<std::size_t> mine;
  for (std::size_t r = rank; r < count; r += size) mine.push_back(r);
  return mine;
}

std::vector<std::string> gather_shares(const RankGroup* ranks, const std::function<std::string()>& work) {
  if (!ranks) return {work()};
  std::string payload;
  std::exception_ptr own;
  try {
    const std::string result = work();
    payload.reserve(result.size() + 1);
    payload.push_back(char(Outcome::done));
    payload.append(result);
  } catch (const InputError& e) {
    own = std::current_exception();
    payload = failure_payload(Outcome::bad_input, e.key(), e.what());
  } catch (const std::exception& e) {
    own = std::current_exception();
    payload = failure_payload(Outcome::failed, "", e.what());
  } catch (...) {
    own = std::current_exception();
    payload = failure_payload(Outcome::failed, "", "an unknown failure");
  }
  std::vector<std::string> parts = ranks->gather(payload);
  // The verdict, from rank 0 to every rank: empty if every rank is done, else the first failure's rank and part.
  std::string verdict;
  if (ranks->rank() == 0)
    for (std::size_t k = 0; k < parts.size() && verdict.empty(); ++k)
      if (parts[k].empty() || Outcome(parts[k][0]) != Outcome::done) {
        StateWriter out;
        out.put(std::uint64_t(k));
        out.put(parts[k]);
        verdict = out.take();
      }
  verdict = ranks->broadcast(verdict);
  if (!verdict.empty()) {
    StateReader in(verdict);
    const int rank = int(in.read<std::uint64_t>());
    std::string failure;
    in.get(failure);
    if (ranks->rank() != 0) throw ShareAbandoned{!failure.empty() && Outcome(failure[0]) == Outcome::bad_input};
    if (own) std::rethrow_exception(own);
    throw_failure(failure, rank);
  }
  for (std::string& part : parts) part.erase(0, 1);
  return parts;
}

std::vector<std::string> gather_realizations(const RankGroup* ranks, std::size_t count,
                                             const std::function<std::vector<std::string>(const std::vector<std::size_t>& mine)>& work) {
  const std::vector<std::size_t> mine = realizations_of_rank(count, ranks);
  if (!ranks) return work(mine);
  const std::vector<std::string> parts = gather_shares(ranks, [&] {
    const std::vector<std::string> results = work(mine);
    if (results.size() != mine.size()) throw std::logic_error("gather_realizations: one result per realization of the rank");
    StateWriter out;
    out.put(std::uint64_t(results.size()));
    for (const std::string& result : results) out.put(result);
    return out.take();
  });
  if (ranks->rank() != 0) return {};
  std::vector<std::string> results(count);
  const std::size_t size = std::size_t(ranks->size());
  for (std::size_t k = 0; k < parts.size(); ++k) {
    StateReader in(parts[k]);
    const std::uint64_t n = in.read<std::uint64_t>();
    std::uint64_t expected = 0;
    for (std::size_t r = k; r < count; r += size) ++expected;
    if (n != expected)
      throw std::runtime_error("MPI rank " + std::to_string(k) + " sent " + std::to_string(n) + " realizations, not " +
                               std::to_string(expected));
    for (std::size_t i = 0; i < n; ++i) in.get(results[k + i * size]);
    in.expect_end();
  }
  return results;
}

void put_measurement(StateWriter& out, const Measurement& m) {
  out.put(m.values);
  out.put(m.leaked_mass);
  out.put(m.distribution);
  out.put(m.sizes);
}

Measurement get_measurement(StateReader& in) {
  Measurement m;
  in.get(m.values);
  in.get(m.leaked_mass);
  in.get(m.distribution);
  in.get(m.sizes);
  return m;
}

}  // namespace aggkit

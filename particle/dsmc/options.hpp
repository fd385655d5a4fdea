#pragma once
// Options of a DSMC run [Kalinov2022]: method (acceptance-rejection or fast DSMC, Algorithms 3–4), initial
// particle count, seeds, grouping of sizes <= B into buckets (Sec. 4) and population control (Sec. 2).
#include <cstddef>
#include <cstdint>
#include <string>

#include "analysis/option_rows.hpp"

namespace aggkit::dsmc {

enum class Method {
  acceptance_rejection,  // "ar": random pair from the binned majorant, accepted with K_ij / K̄ (bin pair)
  fast,                  // "fast": first particle by its exact total rate S_i, partner by K_ij / S_i
};
Method method_from_name(const std::string& name);  // throws InputError (key dsmc.method)
std::string to_string(Method method);

struct Options {
  Method method = Method::acceptance_rejection;
  std::uint64_t particles = 100000;  // initial number of particles N(0) (>= 2); the volume is N(0)/Σ n_k(0)
  std::uint64_t seed = 1;            // master seed of the ensemble (random.hpp: run_seed)
  std::size_t runs = 1;              // independent realisations
  std::uint64_t bucket = 1024;       // B: sizes <= B are grouped in per-size buckets, larger ones stored one by one
  bool truncate = false;             // apply the model's truncation policy and N (default: untruncated system)
  bool population_control = true;    // duplicate all particles when N(t) < N(0)/2 (volume doubles)
  // With population_control, also halve the population by pairs when N(t) > 2 N(0) (volume halves): a
  // shattering population then costs at most 2 N(0) particles, at the price of the larger noise of the
  // smaller simulated volume (the error of a late-time moment grows like 1/sqrt(V)). Off by default: with
  // it the ballistic λ = 0.01 case at 10^6 particles runs ~2.2× faster but its t = 100 errors exceed
  // [Kalinov2022, Table 2] (M2 1.4 % against 0.7 %, M3 3.8 % against 2 %).
  bool population_halving = false;
  std::size_t threads = 0;           // worker threads for an ensemble; 0 = hardware concurrency

  // InputError for a field outside its option row's range (option_rows()).
  void validate() const;
};

// The options of a DSMC run as a scene and Python give them: key, range, doc and the field each sets.
const OptionRows<Options>& option_rows();

}  // namespace aggkit::dsmc

#pragma once
// The final-state files of a particle engine, written by the particle runner from its realizations:
//   <engine>/final.json   each value's mean over the realizations and, with more than one, <key>_stderr (the
//                         standard error of the mean), then "realizations"; non-finite numbers as null
//   <engine>/<name>.csv   each profile (observe.final, e.g. pair_distribution): x, mean y and, with more than
//                         one realization, y_stderr
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "validation/engines/engine.hpp"
#include "validation/observables/observable.hpp"

namespace aggkit {

// Values of the realizations, key by key, in the order the keys first appear.
class FinalAverages {
 public:
  void add(const std::string& key, double value);
  // Mean and standard error of the mean of each key, in order.
  std::vector<FinalStatistic> statistics() const;
  std::string json(std::size_t realizations) const;

 private:
  std::vector<std::string> order_;
  std::map<std::string, std::vector<double>> values_;
};

// One realization's profiles, named as in observe.final.
using NamedProfiles = std::vector<std::pair<std::string, Profile>>;
// Writes <folder>/<name>.csv for each profile from its realizations (same x in each).
void write_final_profiles(const std::filesystem::path& folder, const std::vector<NamedProfiles>& realizations);
// The file names write_final_profiles may write: one per profile observable of the registry.
std::vector<std::string> profile_files();

}  // namespace aggkit

#include "validation/engines/particle_outputs.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "validation/io/atomic_file.hpp"
#include "validation/io/text.hpp"

namespace aggkit {

void FinalAverages::add(const std::string& key, double value) {
  auto& values = values_[key];
  if (values.empty()) order_.push_back(key);
  values.push_back(value);
}

std::vector<FinalStatistic> FinalAverages::statistics() const {
  std::vector<FinalStatistic> out;
  for (const std::string& key : order_) {
    const std::vector<double>& v = values_.at(key);
    double mean = 0;
    for (double x : v) mean += x / double(v.size());
    double variance = 0;
    if (v.size() > 1)
      for (double x : v) variance += (x - mean) * (x - mean) / double(v.size() - 1);
    out.push_back({key, mean, std::sqrt(variance / double(v.size()))});
  }
  return out;
}

std::string FinalAverages::json(std::size_t realizations) const {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  const auto number = [](double x) { return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr); };
  for (const FinalStatistic& s : statistics()) {
    out[s.name] = number(s.mean);
    if (realizations > 1) out[s.name + "_stderr"] = number(s.standard_error);
  }
  out["realizations"] = realizations;
  return out.dump(2) + "\n";
}

void write_final_profiles(const std::filesystem::path& folder, const std::vector<NamedProfiles>& realizations) {
  if (realizations.empty()) return;
  const double count = double(realizations.size());
  for (std::size_t q = 0; q < realizations.front().size(); ++q) {
    const auto& [name, first] = realizations.front()[q];
    AtomicFile csv(folder / (name + ".csv"));
    std::ostream& out = csv.stream();
    out << first.x_name << ',' << first.y_name;
    if (realizations.size() > 1) out << ',' << first.y_name << "_stderr";
    out << '\n';
    for (std::size_t i = 0; i < first.x.size(); ++i) {
      double mean = 0;
      for (const auto& profiles : realizations) mean += profiles[q].second.y[i] / count;
      out << full_precision_text(first.x[i]) << ',' << full_precision_text(mean);
      if (realizations.size() > 1) {
        double variance = 0;
        for (const auto& profiles : realizations)
          variance += (profiles[q].second.y[i] - mean) * (profiles[q].second.y[i] - mean);
        out << ',' << full_precision_text(std::sqrt(variance / (count - 1) / count));
      }
      out << '\n';
    }
    csv.commit();
  }
}

std::vector<std::string> profile_files() {
  std::vector<std::string> files;
  for (const ObservableType& type : observable_types())
    if (type.profile) files.push_back(type.form + ".csv");
  return files;
}

}  // namespace aggkit

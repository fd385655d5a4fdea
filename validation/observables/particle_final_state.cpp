#include "validation/observables/particle_final_state.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "analysis/clusters.hpp"
#include "analysis/fractal_dimension.hpp"
#include "analysis/particle_configuration.hpp"
#include "analysis/shape.hpp"
#include "validation/io/atomic_file.hpp"
#include "validation/io/text.hpp"

namespace aggkit {

const std::vector<std::string>& final_state_observables() {
  static const std::vector<std::string> names{
      "clusters",           "mean_cluster_size", "largest_cluster", "kinetic_energy",
      "contacts",           "contacts_with_self", "aspect_ratio",   "orientation",
      "radius_of_gyration", "fractal_dimension_box", "fractal_dimension_mass", "pair_distribution"};
  return names;
}

std::vector<std::pair<std::string, double>> final_state_values(std::span<const std::string> names,
                                                               const FinalConfiguration& final) {
  const ParticleConfiguration& config = final.config;
  const std::vector<std::size_t> sizes = cluster_sizes(final.cluster);
  std::vector<std::pair<std::string, double>> values;
  bool have_gyration = false;
  Gyration shape;
  const auto gyration_of_largest = [&]() -> const Gyration& {
    if (!have_gyration) shape = gyration(final.largest_cluster, config.dimension);
    have_gyration = true;
    return shape;
  };
  const auto fit = [&](const std::string& name, const FractalFit& f) {
    values.emplace_back(name, f.dimension);
    values.emplace_back(name + "_error", f.standard_error);
    values.emplace_back(name + "_fit_min", f.fit_min);
    values.emplace_back(name + "_fit_max", f.fit_max);
  };
  for (const std::string& name : names) {
    if (name == "clusters") values.emplace_back(name, double(sizes.size()));
    else if (name == "mean_cluster_size") values.emplace_back(name, mean_cluster_size(sizes));
    else if (name == "largest_cluster") values.emplace_back(name, double(final.largest_cluster.size()));
    else if (name == "kinetic_energy") values.emplace_back(name, final.kinetic_energy);
    else if (name == "contacts") values.emplace_back(name, relative_contacts(config, 2.1));
    else if (name == "contacts_with_self")
      values.emplace_back(name, relative_contacts(config, 2.1, ContactCounting::with_self));
    else if (name == "aspect_ratio") values.emplace_back(name, gyration_of_largest().aspect_ratio);
    else if (name == "orientation") values.emplace_back(name, gyration_of_largest().orientation);
    else if (name == "radius_of_gyration") values.emplace_back(name, gyration_of_largest().radius_of_gyration);
    else if (name == "fractal_dimension_box") {
      const double side = config.periodic ? 0.0 : *std::max_element(config.box.begin(), config.box.begin() + config.dimension);
      fit(name, box_counting_dimension(final.largest_cluster, config.dimension, config.radius, side));
    } else if (name == "fractal_dimension_mass") {
      fit(name, mass_radius_dimension(final.largest_cluster, config.dimension, config.radius));
    } else if (name != "pair_distribution") {  // a profile: final_profiles
      throw std::logic_error("unknown final-state observable " + name);  // the scene parser checked the names
    }
  }
  return values;
}

std::vector<FinalProfile> final_profiles(std::span<const std::string> names, const FinalConfiguration& final) {
  std::vector<FinalProfile> profiles;
  for (const std::string& name : names) {
    if (name != "pair_distribution") continue;
    const PairDistribution p = pair_distribution(final.config, pair_distribution_radii(final.config.radius, 90));
    profiles.push_back({name, "r", "P", p.r, p.p});
  }
  return profiles;
}

void write_final_profiles(const std::filesystem::path& folder, const std::vector<std::vector<FinalProfile>>& realizations) {
  if (realizations.empty()) return;
  const double count = double(realizations.size());
  for (std::size_t q = 0; q < realizations.front().size(); ++q) {
    const FinalProfile& first = realizations.front()[q];
    AtomicFile csv(folder / (first.name + ".csv"));
    std::ostream& out = csv.stream();
    out << first.x_name << ',' << first.y_name;
    if (realizations.size() > 1) out << ',' << first.y_name << "_stderr";
    out << '\n';
    for (std::size_t i = 0; i < first.x.size(); ++i) {
      double mean = 0;
      for (const auto& profiles : realizations) mean += profiles[q].y[i] / count;
      out << full_precision_text(first.x[i]) << ',' << full_precision_text(mean);
      if (realizations.size() > 1) {
        double variance = 0;
        for (const auto& profiles : realizations) variance += (profiles[q].y[i] - mean) * (profiles[q].y[i] - mean);
        out << ',' << full_precision_text(std::sqrt(variance / (count - 1) / count));
      }
      out << '\n';
    }
    csv.commit();
  }
}

}  // namespace aggkit

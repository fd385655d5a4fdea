#include "validation/harness/series_output.hpp"

#include "validation/io/atomic_file.hpp"
#include "solvers/size_grid.hpp"
#include "validation/io/text.hpp"

namespace aggkit {

void write_series_csv(const std::filesystem::path& file, const Observation& observe, const EngineRecord& record) {
  AtomicFile csv(file);
  std::ostream& out = csv.stream();
  out << "t";
  for (const auto& observable : observe.series) out << ',' << observable.name();
  const bool ensemble = !record.standard_errors.empty();
  if (ensemble)
    for (const auto& observable : observe.series) out << ',' << observable.name() << "_stderr";
  out << '\n';
  for (std::size_t i = 0; i < record.times.size(); ++i) {
    out << full_precision_text(record.times[i]);
    for (double value : record.values[i]) out << ',' << full_precision_text(value);
    if (ensemble)
      for (double error : record.standard_errors[i]) out << ',' << full_precision_text(error);
    out << '\n';
  }
  csv.commit();
}

void write_distribution_csv(const std::filesystem::path& file, const EngineRecord& record, const SizeGrid& grid) {
  AtomicFile csv(file);
  std::ostream& out = csv.stream();
  out << "t,k,n,cdf\n";
  for (const auto& distribution : record.distributions) {
    const std::string t = full_precision_text(distribution.t);
    double total = 0;
    for (double n : distribution.n) total += n;
    double below = 0;  // Σ_{j<=k} n_j: the cdf is the fraction of clusters of size <= k
    if (!distribution.sizes.empty()) {
      // A graded grid: one row per pivot, k its size and n the density per unit size the pivot's number
      // stands for (solvers/size_grid.hpp section_densities; the n_k of a uniform grid where the pivots
      // are the integers); the cdf counts the clusters of the pivots <= k.
      const std::vector<double> density =
          section_densities(distribution.sizes, distribution.n, grid.scheme, grid.resolved);
      for (std::size_t i = 0; i < distribution.n.size(); ++i) {
        below += distribution.n[i];
        out << t << ',' << full_precision_text(distribution.sizes[i]) << ','
            << full_precision_text(density[i]) << ','
            << full_precision_text(total != 0 ? below / total : 0.0) << '\n';
      }
      continue;
    }
    for (std::size_t k = 1; k <= distribution.n.size(); ++k) {
      below += distribution.n[k - 1];
      out << t << ',' << k << ',' << full_precision_text(distribution.n[k - 1]) << ','
          << full_precision_text(total != 0 ? below / total : 0.0) << '\n';
    }
  }
  csv.commit();
}

}  // namespace aggkit

#pragma once
// The bin-pair tables of the binned majorant [Michelotti2013] on a population padded with empty slots.
//
// Bin b is given m_b >= n_b slots: its n_b particles and m_b - n_b empty ones ("ghosts", whose kernel with
// anything is 0). The majorant pair process runs on ordered pairs of distinct slots, the pair of slots in
// bins (b, c) at rate K̄(b, c): bin b with weight m_b Σ_c K̄(b,c)(m_c - δ_bc), bin c with weight
// K̄(b,c)(m_c - δ_bc), then a uniform slot in each. A pair with a ghost is rejected (its kernel is 0 <= K̄),
// a pair of particles is accepted with K_ij / K̄(b, c): the accepted pairs are those of the exact process, as
// for any majorant of the kernel on a superset of the population ([Eibeck2001]: the majorant need only bound
// the kernel; the ghosts' kernel is 0). What the slots buy is that the tables depend on the capacities m_b
// only, not on the counts: they are rebuilt in O(bins²) when a count leaves the band [low_b, m_b] set at the
// last rebuild, instead of the row sums being updated in O(bins) at every event, and each bin is chosen in
// O(1) from an alias table [Walker1977] (built by Vose's method [Vose1991]) instead of a scan.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "particle/common/checkpoint.hpp"
#include "particle/dsmc/size_bins.hpp"

namespace aggkit::dsmc {

class SlotMajorant {
 public:
  SlotMajorant();

  // Capacities from the counts n_b of bins < `bins` (m_b = n_b + slack, low_b = n_b - slack), then the tables.
  void set_capacities(const std::uint64_t* counts, std::size_t bins);
  // The tables from the capacities, the majorant K̄ (max_bins × max_bins, symmetric) and the counts (for the
  // weight of the pairs of particles, which tells whether any pair can interact).
  void build(const double* majorant, const std::uint64_t* counts);

  std::size_t bins() const { return bins_; }
  double total() const { return total_; }                // W = Σ over ordered pairs of distinct slots of K̄
  bool particles_interact() const { return real_ > 0.0; }  // Σ over ordered pairs of particles of K̄ > 0
  std::uint64_t capacity(std::size_t b) const { return capacity_[b]; }
  // Whether a count still lies in its bin's band (a bin beyond the tables never does).
  bool holds(std::size_t b, std::uint64_t count) const {
    return b < bins_ && count <= capacity_[b] && count >= low_[b];
  }

  // The first bin for u uniform in [0, 1); the second, for v uniform in [0, 1), given the first.
  std::size_t first(double u) const { return sample(first_.data(), u); }
  std::size_t second(std::size_t b, double v) const { return sample(&second_[b * bins_], v); }

  void save(StateWriter& out) const;
  void restore(StateReader& in, const double* majorant, const std::uint64_t* counts);

 private:
  struct Cell {  // one cell of an alias table: its own index with probability `keep`, else `alias`
    double keep;
    std::uint64_t alias;
  };
  // Cell floor(u n), then the cell's own index or its alias by the fractional part of u n — without a
  // branch: the choice is a coin flip, which a branch would mispredict about every other trial.
  std::size_t sample(const Cell* table, double u) const {
    const double x = u * double(std::int64_t(bins_));
    std::int64_t k = std::int64_t(x);
    k = k < std::int64_t(bins_) - 1 ? k : std::int64_t(bins_) - 1;
    const Cell& cell = table[k];
    const std::uint64_t own = std::uint64_t(0) - std::uint64_t(x - double(k) < cell.keep);  // all ones: keep k
    return std::size_t((std::uint64_t(k) & own) | (cell.alias & ~own));
  }
  struct Scratch {  // the rebuild's working arrays, kept between rebuilds
    std::vector<double> row, first, scaled;
    std::vector<std::size_t> small, large;
  };
  static void alias_table(const double* weights, std::size_t n, Cell* table, Scratch& scratch);

  std::size_t bins_ = 0;  // bins with capacities (the tables' length)
  std::vector<std::uint64_t> capacity_, low_;
  std::vector<Cell> first_;   // first bin: weights m_b Σ_c K̄(b,c)(m_c - δ_bc)
  std::vector<Cell> second_;  // row b (at b·bins_): weights K̄(b,c)(m_c - δ_bc) over c
  double total_ = 0.0;
  double real_ = 0.0;
  Scratch scratch_;
};

}  // namespace aggkit::dsmc

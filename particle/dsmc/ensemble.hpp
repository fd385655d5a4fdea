#pragma once
// Independent DSMC realisations run side by side in threads. Run r uses the seed run_seed(seed, r)
// (random.hpp); runs are assigned to threads statically and each owns its generator, so the results do
// not depend on the number of threads: the same master seed gives the same series bit for bit on the
// same build. The runs advance together from output time to output time, so only one snapshot per run
// is held at a time.
#include <functional>
#include <memory>
#include <vector>

#include "particle/dsmc/simulation.hpp"

namespace aggkit::dsmc {

class Ensemble {
 public:
  Ensemble(const AggregationModel& model, const Options& options, double t_end);
  // Only the runs numbered `runs` of the options' ensemble (each with its seed run_seed(seed, r)), in that
  // order: a share of the ensemble (the runs of one MPI rank); run(i) and advance_to's run index count
  // within the share.
  Ensemble(const AggregationModel& model, const Options& options, double t_end, const std::vector<std::size_t>& runs);

  // Advances every realisation to t (in parallel) and returns their states, in run order. `every`, if given,
  // is called as every(run, time) from the thread running that run every 2^20 trials (Simulation::advance_to);
  // run 0 always runs on the calling thread.
  std::vector<Snapshot> advance_to(double t, const std::function<void(std::size_t run, double time)>& every = {});
  std::size_t runs() const { return runs_.size(); }
  std::size_t threads() const { return threads_; }
  const Simulation& run(std::size_t r) const { return *runs_[r]; }
  void save(StateWriter& out) const;  // every realisation (Simulation::save)
  void restore(StateReader& in);

 private:
  std::vector<std::unique_ptr<Simulation>> runs_;
  std::size_t threads_ = 1;
};

// Mean and standard error of the mean (sample standard deviation / sqrt(R); 0 for R = 1).
struct MeanAndError {
  double mean;
  double standard_error;
};
MeanAndError mean_and_error(const std::vector<double>& values);

}  // namespace aggkit::dsmc

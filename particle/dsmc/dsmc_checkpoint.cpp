// Checkpoints of the DSMC engine: save and restore of the steppers, the population, a simulation and an
// ensemble (declared beside each class).
#include "particle/dsmc/acceptance_rejection.hpp"
#include "particle/dsmc/binned_population.hpp"
#include "particle/dsmc/ensemble.hpp"
#include "particle/dsmc/fast_dsmc.hpp"
#include "particle/dsmc/simulation.hpp"

namespace aggkit::dsmc {

void BinnedPopulation::save(StateWriter& out) const {
  out.put(limit_);
  out.put(bucket_);
  // The checkpoint keeps the layout of one Fenwick tree over all bucketed sizes (built here from the
  // buckets); restore() rebuilds the bin trees from the buckets.
  Fenwick all(limit_);
  all.assign(bucket_);
  all.save(out);
  out.put(std::uint64_t(bins_.size()));
  for (const Bin& bin : bins_) {
    out.put(bin.count);
    out.put(bin.small);
    out.put(bin.large);
  }
  out.put(particles_);
}

void BinnedPopulation::restore(StateReader& in) {
  in.expect(limit_, "DSMC bucket limit");
  const std::size_t buckets = bucket_.size();
  in.get(bucket_);
  if (bucket_.size() != buckets) throw CheckpointError("the checkpoint's DSMC buckets have another length");
  Fenwick all(limit_);
  all.restore(in);  // read past: the bin trees follow from the buckets
  rebuild_trees();
  bins_.resize(in.length(3 * sizeof(std::uint64_t)));  // a bin: count, small, the length of large
  for (Bin& bin : bins_) {
    in.get(bin.count);
    in.get(bin.small);
    in.get(bin.large);
  }
  in.get(particles_);
}

void AcceptanceRejection::save(StateWriter& out) const {
  population_.save(out);
  out.put(majorant_);
  out.put(std::uint64_t(known_));
  // The slot tables are rebuilt from the saved capacities (the same bits); the counts are the population's.
  slots_.save(out);
  out.put(std::uint8_t(dirty_));
  out.put(leaked_);
}

void AcceptanceRejection::restore(StateReader& in) {
  population_.restore(in);
  const std::size_t majorant = majorant_.size();
  in.get(majorant_);
  if (majorant_.size() != majorant) throw CheckpointError("the checkpoint's DSMC majorant has another size");
  known_ = std::size_t(in.read<std::uint64_t>());
  if (known_ > max_bins || population_.bins() > known_)
    throw CheckpointError("the checkpoint's DSMC majorant covers another number of bins");
  slots_.restore(in, majorant_.data(), counts());
  dirty_ = in.read<std::uint8_t>() != 0;
  in.get(leaked_);
}

void FastDsmc::save(StateWriter& out) const {
  out.put(limit_);
  out.put(groups_);
  out.put(slot_);
  out.put(particles_);
  out.put(leaked_);
  out.put(total_weight_);
  out.put(events_since_refresh_);
}

void FastDsmc::restore(StateReader& in) {
  in.expect(limit_, "DSMC bucket limit");
  in.get(groups_);
  const std::size_t slots = slot_.size();
  in.get(slot_);
  if (slot_.size() != slots) throw CheckpointError("the checkpoint's DSMC size slots have another length");
  for (std::size_t g : slot_)
    if (g != npos && g >= groups_.size()) throw CheckpointError("the checkpoint's DSMC size slots name a group beyond the count");
  in.get(particles_);
  in.get(leaked_);
  in.get(total_weight_);
  in.get(events_since_refresh_);
}

void Simulation::save(StateWriter& out) const {
  stepper_->save(out);
  out.put(random_);
  out.put(time_);
  out.put(volume_);
  out.put(next_trial_);
  out.put(next_lambda_);
  out.put(initial_particles_);
  out.put(initial_mass_);
  out.put(control_mass_);
  out.put(rejections_in_a_row_);
  out.put(statistics_);
}

void Simulation::restore(StateReader& in) {
  stepper_->restore(in);
  in.get(random_);
  in.get(time_);
  in.get(volume_);
  in.get(next_trial_);
  in.get(next_lambda_);
  in.expect(initial_particles_, "initial DSMC particle count");
  in.expect(initial_mass_, "initial DSMC mass");
  in.get(control_mass_);
  in.get(rejections_in_a_row_);
  in.get(statistics_);
}

void Ensemble::save(StateWriter& out) const {
  out.put(std::uint64_t(runs_.size()));
  for (const auto& run : runs_) run->save(out);
}

void Ensemble::restore(StateReader& in) {
  in.expect(std::uint64_t(runs_.size()), "number of DSMC runs");
  for (auto& run : runs_) run->restore(in);
}

}  // namespace aggkit::dsmc

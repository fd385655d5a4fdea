#include "particle/dsmc/ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <thread>

namespace aggkit::dsmc {

namespace {
std::vector<std::size_t> every_run(std::size_t runs) {
  std::vector<std::size_t> all(runs);
  for (std::size_t r = 0; r < runs; ++r) all[r] = r;
  return all;
}
}  // namespace

Ensemble::Ensemble(const AggregationModel& model, const Options& options, double t_end)
    : Ensemble(model, options, t_end, every_run(options.runs)) {}

Ensemble::Ensemble(const AggregationModel& model, const Options& options, double t_end, const std::vector<std::size_t>& runs) {
  options.validate();
  for (std::size_t r : runs) runs_.push_back(std::make_unique<Simulation>(model, options, run_seed(options.seed, r), t_end));
  const std::size_t hardware = std::max(1u, std::thread::hardware_concurrency());
  threads_ = std::max<std::size_t>(1, std::min(runs_.size(), options.threads == 0 ? hardware : options.threads));
}

std::vector<Snapshot> Ensemble::advance_to(double t, const std::function<void(std::size_t run, double time)>& every) {
  std::vector<Snapshot> snapshots(runs_.size());
  std::vector<std::exception_ptr> failures(threads_);
  const auto work = [&](std::size_t worker) {
    try {
      for (std::size_t r = worker; r < runs_.size(); r += threads_) {
        if (every) runs_[r]->advance_to(t, [&every, r](double time) { every(r, time); });
        else runs_[r]->advance_to(t);
        snapshots[r] = runs_[r]->snapshot();
      }
    } catch (...) {
      failures[worker] = std::current_exception();
    }
  };
  std::vector<std::thread> workers;
  for (std::size_t w = 1; w < threads_; ++w) workers.emplace_back(work, w);
  work(0);
  for (auto& worker : workers) worker.join();
  for (const auto& failure : failures)
    if (failure) std::rethrow_exception(failure);
  return snapshots;
}

MeanAndError mean_and_error(const std::vector<double>& values) {
  const double n = double(values.size());
  double mean = 0.0;
  for (double v : values) mean += v;
  mean /= n;
  if (values.size() < 2) return {mean, 0.0};
  double squares = 0.0;
  for (double v : values) squares += (v - mean) * (v - mean);
  return {mean, std::sqrt(squares / (n - 1.0) / n)};
}

}  // namespace aggkit::dsmc

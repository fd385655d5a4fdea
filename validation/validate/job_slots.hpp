#pragma once
// Which scene of a validation starts next and how many job slots (cores) it holds: `aggkit validate --jobs K`
// has K slots. A run scene holds one; a scene that can spread its work over MPI ranks (a scan: its points are
// drawn from a shared counter by the ranks) takes every free slot it can use when it starts, up to its
// `max_slots`, and runs on that many ranks (validate.cpp). Scenes start in order of priority, highest first
// (the long ones first, so that the short ones fill the cores at the end), ties in the order given; whenever
// a slot is free the next scene starts, with the slots free then. No slot is ever left idle while a scene
// waits, and a started scene keeps its slots until it ends: an MPI job cannot take ranks while it runs.
#include <cstddef>
#include <optional>
#include <vector>

namespace aggkit {

struct SlotDemand {
  std::size_t max_slots = 1;  // the most slots the job can use (at least 1)
  int priority = 0;           // higher starts first
};

class SlotScheduler {
 public:
  SlotScheduler(std::vector<SlotDemand> jobs, std::size_t slots);

  struct Start {
    std::size_t job = 0;    // index into the jobs given
    std::size_t slots = 0;  // the slots it holds until finished(job)
  };
  // The next job to start now and the slots it takes; nullopt when every job has started or no slot is free.
  std::optional<Start> next();
  // The job has ended: its slots are free again.
  void finished(std::size_t job);

  std::size_t free_slots() const { return free_; }
  std::size_t held_by(std::size_t job) const { return held_.at(job); }
  bool all_started() const { return next_ == order_.size(); }

 private:
  std::vector<SlotDemand> jobs_;
  std::vector<std::size_t> order_;  // the jobs in the order they start
  std::size_t next_ = 0;            // into order_
  std::vector<std::size_t> held_;   // slots held by each job (0: not started or ended)
  std::size_t free_ = 0;
};

}  // namespace aggkit

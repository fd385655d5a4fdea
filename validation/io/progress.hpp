#pragma once
// Progress of a long run on stderr: engine, time reached / end, elapsed wall time, at most about once a
// second; nothing for runs shorter than that.
#include <chrono>
#include <ostream>
#include <string>

namespace aggkit {

class Progress {
 public:
  // `out` == nullptr: quiet.
  explicit Progress(std::ostream* out, std::chrono::duration<double> interval = std::chrono::seconds(1));

  void start(const std::string& engine, std::size_t index, std::size_t count, double end);
  void set_end(double end) { end_ = end; }  // a run whose length is known only once it starts
  void reached(double t);  // prints if `interval` has passed since the start or the last line
  void note(const std::string& what);  // the same for a line in words (a stage, a count)
  void finish();           // the total time, if anything was printed for this engine

 private:
  using Clock = std::chrono::steady_clock;
  double elapsed() const;
  bool due();  // `interval` has passed since the start or the last line: then true, and the clock restarts
  std::ostream* out_;
  std::chrono::duration<double> interval_;
  std::string engine_;
  std::size_t index_ = 0, count_ = 0;
  double end_ = 0.0;
  Clock::time_point started_, last_;
  bool printed_ = false;
};

}  // namespace aggkit

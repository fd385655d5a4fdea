#include "validation/io/progress.hpp"

#include <cstdio>

namespace aggkit {

Progress::Progress(std::ostream* out, std::chrono::duration<double> interval) : out_(out), interval_(interval) {}

double Progress::elapsed() const { return std::chrono::duration<double>(Clock::now() - started_).count(); }

void Progress::start(const std::string& engine, std::size_t index, std::size_t count, double end) {
  engine_ = engine;
  index_ = index;
  count_ = count;
  end_ = end;
  started_ = last_ = Clock::now();
  printed_ = false;
}

bool Progress::due() {
  if (!out_) return false;
  const auto now = Clock::now();
  if (now - last_ < interval_) return false;
  last_ = now;
  printed_ = true;
  return true;
}

void Progress::reached(double t) {
  if (!due()) return;
  char line[256];
  std::snprintf(line, sizeof line, "aggkit: engine %zu/%zu %s: t = %.6g / %.6g (%.0f%%), %.1f s\n", index_, count_,
                engine_.c_str(), t, end_, end_ > 0 ? 100.0 * t / end_ : 100.0, elapsed());
  *out_ << line << std::flush;
}

void Progress::note(const std::string& what) {
  if (!due()) return;
  char line[64];
  std::snprintf(line, sizeof line, ", %.1f s\n", elapsed());
  *out_ << "aggkit: engine " << index_ << '/' << count_ << ' ' << engine_ << ": " << what << line << std::flush;
}

void Progress::finish() {
  if (!out_ || !printed_) return;
  char line[256];
  std::snprintf(line, sizeof line, "aggkit: engine %zu/%zu %s: done in %.1f s\n", index_, count_, engine_.c_str(), elapsed());
  *out_ << line << std::flush;
}

}  // namespace aggkit

#include "particle/dsmc/options.hpp"

#include "analysis/input_error.hpp"

namespace aggkit::dsmc {

Method method_from_name(const std::string& name) {
  if (name == "ar") return Method::acceptance_rejection;
  if (name == "fast") return Method::fast;
  throw InputError("method", "\"" + name + "\"", "ar (acceptance-rejection) or fast (two-stage fast DSMC)");
}

std::string to_string(Method method) { return method == Method::fast ? "fast" : "ar"; }

void Options::validate() const {
  if (particles < 2)
    throw InputError("particles", std::to_string(particles), "an integer >= 2 (a pair is needed to collide)");
  if (runs < 1) throw InputError("runs", std::to_string(runs), "an integer >= 1");
  if (bucket < 1) throw InputError("bucket", std::to_string(bucket), "an integer >= 1 (largest bucketed size)");
  if (bucket > (std::uint64_t(1) << 26))
    throw InputError("bucket", std::to_string(bucket), "at most 2^26 (buckets cost memory for every size up to B)");
}

}  // namespace aggkit::dsmc

#include "particle/dsmc/options.hpp"

#include "analysis/input_error.hpp"

namespace aggkit::dsmc {

Method method_from_name(const std::string& name) {
  if (name == "ar") return Method::acceptance_rejection;
  if (name == "fast") return Method::fast;
  throw InputError("method", "\"" + name + "\"", "ar (acceptance-rejection) or fast (two-stage fast DSMC)");
}

std::string to_string(Method method) { return method == Method::fast ? "fast" : "ar"; }

void Options::validate() const { option_rows().check(*this); }

const OptionRows<Options>& option_rows() {
  using B = Bind<Options>;
  static const OptionRows<Options> rows{{
      B::named("method", &Options::method, std::vector{Method::acceptance_rejection, Method::fast},
               "acceptance-rejection against a binned majorant, or two-stage fast DSMC"),
      B::integer("particles", &Options::particles, closed(2, 1e12), "initial number of particles N(0)"),
      B::integer("seed", &Options::seed, at_least(0), "master seed of the ensemble"),
      B::integer("runs", &Options::runs, closed(1, 1e6), "independent realisations (threads); > 1 gives standard errors"),
      // Buckets cost memory for every size up to B.
      B::integer("bucket", &Options::bucket, closed(1, 67108864), "sizes <= bucket are grouped per size"),
      B::flag("truncate", &Options::truncate, "apply model.size and model.truncation (default: the untruncated system)"),
      B::flag("population_control", &Options::population_control, "duplicate the population when it falls below N(0)/2"),
      B::flag("population_halving", &Options::population_halving,
              "with population_control, halve the population by pairs when it exceeds 2 N(0) (faster, noisier late)"),
      B::integer("threads", &Options::threads, at_least(0), "worker threads (0: every core)"),
  }};
  return rows;
}

}  // namespace aggkit::dsmc

// The observables a scene can ask for: one entry each. To add one, add an entry here (form, description,
// what it needs of a state, how its name is matched, how it is computed).
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

#include "analysis/fractal_dimension.hpp"
#include "analysis/least_squares.hpp"
#include "analysis/oscillation.hpp"
#include "analysis/shape.hpp"
#include "validation/observables/observable.hpp"

namespace aggkit {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// Parses all of `text` as a number of type T; std::nullopt unless the whole text is one number.
template <class T>
std::optional<T> parse_whole(std::string_view text) {
  T value{};
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  if (text.empty() || result.ec != std::errc() || result.ptr != end) return std::nullopt;
  return value;
}

// A plain name: parameter 0.
std::function<std::optional<double>(std::string_view)> named(std::string name) {
  return [name = std::move(name)](std::string_view text) -> std::optional<double> {
    return text == name ? std::optional<double>(0.0) : std::nullopt;
  };
}

// M<p>: a plain decimal order p >= 0 (from_chars would also read "nan", "inf" and a sign).
std::optional<double> moment_order(std::string_view name) {
  if (name.size() < 2 || name.front() != 'M') return std::nullopt;
  const std::string_view rest = name.substr(1);
  if (!(std::isdigit(static_cast<unsigned char>(rest.front())) || rest.front() == '.')) return std::nullopt;
  const auto p = parse_whole<double>(rest);
  if (!p || !std::isfinite(*p) || *p < 0) return std::nullopt;
  return *p;
}

// n<k>: an integer k >= 1.
std::optional<double> density_size(std::string_view name) {
  if (name.size() < 2 || name.front() != 'n' || !std::isdigit(static_cast<unsigned char>(name[1]))) return std::nullopt;
  const auto k = parse_whole<std::size_t>(name.substr(1));
  if (!k || *k < 1) return std::nullopt;
  return double(*k);
}

// "<measure>:<series>" with a non-empty series name (checked against observe.series by the scene).
std::function<std::optional<double>(std::string_view)> of_a_series(std::string measure) {
  return [prefix = std::move(measure) + ":"](std::string_view text) -> std::optional<double> {
    return text.size() > prefix.size() && text.substr(0, prefix.size()) == prefix ? std::optional<double>(0.0)
                                                                                  : std::nullopt;
  };
}

// An oscillation measure over every cycle of the series (the whole of it is the window: tail_fraction 1), by
// analysis/oscillation.hpp's turning points; NaN without a complete cycle or for a series it rejects.
std::function<double(std::span<const double>, std::span<const double>)> oscillation(
    double OscillationClassification::*field) {
  return [field](std::span<const double> t, std::span<const double> x) {
    OscillationCriteria criteria;
    criteria.tail_fraction = 1.0;
    // A turning point needs a reversal of 30 % of the half swing (the classifier's 10 % is for smooth
    // solver output): one DSMC run of 3·10^4 particles carries noise of ~4 % of the half swing of M0 at
    // a = 0.95, λ = 0.01, which made spurious cycles at 10 % and none at 30 % (nor at 50 %: the count is stable).
    criteria.prominence = 0.3;
    try {
      const OscillationClassification c = classify_oscillation(t, x, criteria);
      return c.cycles >= 1 ? c.*field : nan;
    } catch (const std::exception&) {
      return nan;  // too short, non-finite (a DSMC run that died out): no measure
    }
  };
}

// A number of the particle configuration; NaN for a state without one.
std::function<double(const ObservedState&, double)> of_particles(double (*f)(const ParticleView&)) {
  return [f](const ObservedState& state, double) { return state.particles() ? f(*state.particles()) : nan; };
}

const Gyration gyration_of_largest(const ParticleView& v) {
  return gyration(v.largest_cluster(), v.configuration().dimension);
}

// N(r) about the centre of mass of all particles at r_k = R·2^(k/2), k = 2, 3, ... (R the configuration's
// radius, the mean for unequal radii): fitted by least squares in log-log from 2R up to r_90, the distance
// holding 90 % of the particles (particles that escaped the aggregate stay out of the fit), at least 3
// scales (else NaN). Rule "centre_of_mass".
// `whole_range`: every sphere enters, the scales running from 2R to the first r_k at or beyond the farthest
// particle (N = every particle there) — a reading of [Trivino2025, Sec. V], which states neither the fit's
// range nor which particles enter. Rule "centre_of_mass_all".
FractalFit centre_of_mass_dimension(const ParticleConfiguration& c, std::span<const double> masses, bool whole_range = false) {
  FractalFit fit;
  fit.rule = whole_range ? "centre_of_mass_all" : "centre_of_mass";
  fit.dimension = fit.standard_error = fit.fit_min = fit.fit_max = nan;
  const std::size_t n = c.positions.size();
  if (n < 2 || masses.size() != n) return fit;
  std::array<double, 3> centre{0, 0, 0};
  double total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (int d = 0; d < 3; ++d) centre[d] += masses[i] * c.positions[i][d];
    total += masses[i];
  }
  for (int d = 0; d < 3; ++d) centre[d] /= total;
  std::vector<double> distance(n);
  for (std::size_t i = 0; i < n; ++i) {
    double r2 = 0;
    for (int d = 0; d < 3; ++d) r2 += (c.positions[i][d] - centre[d]) * (c.positions[i][d] - centre[d]);
    distance[i] = std::sqrt(r2);
  }
  for (double d : distance)
    if (!std::isfinite(d)) return fit;  // a state that blew up (non-finite positions): no fit
  std::sort(distance.begin(), distance.end());
  const double r90 = distance[std::min(n - 1, std::size_t(std::ceil(0.9 * double(n))) - 1)];
  std::vector<double> log_scale, log_count;  // the scales holding at least one particle
  for (int k = 2;; ++k) {
    const double r = c.radius * std::pow(2.0, 0.5 * k);
    if (whole_range ? r / std::sqrt(2.0) >= distance.back() && k > 2 : r > r90) break;
    const double count = double(std::upper_bound(distance.begin(), distance.end(), r) - distance.begin());
    fit.scale.push_back(r);
    fit.count.push_back(count);
    if (count < 1) continue;
    log_scale.push_back(std::log(r));
    log_count.push_back(std::log(count));
    if (fit.fit_points++ == 0) fit.fit_min = r;
    fit.fit_max = r;
  }
  if (fit.fit_points < 3) return fit;
  // Least squares with the slope's standard error sqrt(Σ residual² / (n - 2) / Σ (x - x̄)²)
  // (analysis/least_squares.hpp, gsl_fit_linear).
  const LineFit line = fit_line(log_scale, log_count);
  fit.dimension = line.slope;
  fit.standard_error = line.slope_error;
  return fit;
}

// A number of the collision statistics and the configuration (volume V, dimension d, count N); NaN for a
// state without them or before any time has passed.
std::function<double(const ObservedState&, double)> of_collisions(double (*f)(const CollisionStatistics&, const ParticleConfiguration&)) {
  return [f](const ObservedState& state, double) {
    const ParticleView* v = state.particles();
    if (!v || !v->collision_statistics() || !(v->collision_statistics()->time > 0)) return nan;
    return f(*v->collision_statistics(), v->configuration());
  };
}

double box_volume(const ParticleConfiguration& c) {
  double volume = 1;
  for (int d = 0; d < c.dimension; ++d) volume *= c.box[d];
  return volume;
}

// The densities' measures: moments, densities of one size, the mass leaked by truncation.
std::vector<ObservableType> density_types() {
  using namespace need;
  return {
      {"M<p>", "moment M_p = Σ_k k^p n_k, real p >= 0 (M0, M1, M1.5, ...)", sizes, moment_order, false,
       [](const ObservedState& s, double p) { return s.moment(p); }, {}, {}},
      {"n<k>", "density n_k of size k >= 1 (n1, n10, ...)", sizes, density_size, true,
       [](const ObservedState& s, double k) { return s.density(std::size_t(k)); }, {}, {}},
      {"mass_leak", "mass lost through the truncation so far (truncation = \"drop\")", need::leaked_mass,
       named("mass_leak"), false, [](const ObservedState& s, double) { return s.leaked_mass(); }, {}, {}},
  };
}

// The clusters and contacts of a particle configuration, and its kinetic energy.
std::vector<ObservableType> cluster_types() {
  using namespace need;
  return {
      {"clusters", "number of clusters", need::clusters, named("clusters"), false,
       of_particles([](const ParticleView& v) { return double(v.clusters()); }), {}, {}},
      {"mean_cluster_size", "particles per cluster N/C; M1/M0 for densities", sizes, named("mean_cluster_size"), false,
       [](const ObservedState& s, double) {
         if (const ParticleView* v = s.particles()) return double(v->count()) / double(v->clusters());
         return s.moment(1) / s.moment(0);
       }, {}, {}},
      {"components_fraction", "C/N_tot: clusters (components of the engine's contact graph) per particle [Trivino2025]",
       need::clusters, named("components_fraction"), false,
       of_particles([](const ParticleView& v) { return double(v.clusters()) / double(v.count()); }), {}, {}},
      {"largest_cluster", "particle count of the largest cluster", need::clusters, named("largest_cluster"), false,
       of_particles([](const ParticleView& v) {
         const auto sizes = v.cluster_sizes();
         return double(*std::max_element(sizes.begin(), sizes.end()));
       }), {}, {}},
      {"kinetic_energy", "Σ ½ m |v|² over the particles", velocities | masses, named("kinetic_energy"), false,
       of_particles([](const ParticleView& v) { return v.kinetic_energy(); }), {}, {}},
      {"contacts", "relative contacts per sphere N_c within 2.1 R (N_max = 6 in 2-D, 12 in 3-D) [Degond2024]",
       positions, named("contacts"), false,
       of_particles([](const ParticleView& v) { return relative_contacts(v.configuration(), 2.1); }), {}, {}},
      {"contacts_with_self", "N_c with the i = j terms counted (+1/N_max), the reading of the published ≈ 0.5 [Degond2024]",
       positions, named("contacts_with_self"), false,
       of_particles([](const ParticleView& v) {
         return relative_contacts(v.configuration(), 2.1, ContactCounting::with_self);
       }), {}, {}},
  };
}

// The shape of the largest cluster: gyration and fractal dimensions.
std::vector<ObservableType> shape_types() {
  using namespace need;
  return {
      {"aspect_ratio", "aspect ratio of the gyration tensor of the largest cluster", positions | need::clusters,
       named("aspect_ratio"), false,
       of_particles([](const ParticleView& v) { return gyration_of_largest(v).aspect_ratio; }), {}, {}},
      {"orientation", "orientation of the gyration tensor's main axis (largest cluster)", positions | need::clusters,
       named("orientation"), false,
       of_particles([](const ParticleView& v) { return gyration_of_largest(v).orientation; }), {}, {}},
      {"radius_of_gyration", "radius of gyration of the largest cluster", positions | need::clusters,
       named("radius_of_gyration"), false,
       of_particles([](const ParticleView& v) { return gyration_of_largest(v).radius_of_gyration; }), {}, {}},
      {"fractal_dimension_box",
       "box-counting dimension of the largest cluster (grid over the box side with walls, over its own bounding "
       "box when periodic), with _error, _fit_min, _fit_max",
       positions | need::clusters, named("fractal_dimension_box"), false, {},
       [](const ParticleView& v) {
         const ParticleConfiguration& c = v.configuration();
         const double side = c.periodic ? 0.0 : *std::max_element(c.box.begin(), c.box.begin() + c.dimension);
         return box_counting_dimension(v.largest_cluster(), c.dimension, c.radius, side);
       },
       {}},
      {"fractal_dimension_mass", "mass-radius dimension N(r) of the largest cluster, with _error, _fit_min, _fit_max",
       positions | need::clusters, named("fractal_dimension_mass"), false, {},
       [](const ParticleView& v) {
         const ParticleConfiguration& c = v.configuration();
         return mass_radius_dimension(v.largest_cluster(), c.dimension, c.radius);
       },
       {}},
      {"fractal_dimension_com",
       "slope F of log N(r) against log r, N(r) the particles within r of the centre of mass of all particles, with "
       "_error, _fit_min, _fit_max [Trivino2025]",
       positions | masses, named("fractal_dimension_com"), false, {},
       [](const ParticleView& v) { return centre_of_mass_dimension(v.configuration(), v.masses()); }, {}},
      {"fractal_dimension_com_all",
       "fractal_dimension_com fitted over every sphere, from 2R to the farthest (the first scale R·2^(k/2) holding them "
       "all), with _error, _fit_min, _fit_max [Trivino2025]",
       positions | masses, named("fractal_dimension_com_all"), false, {},
       [](const ParticleView& v) { return centre_of_mass_dimension(v.configuration(), v.masses(), true); }, {}},
  };
}

// The collision statistics of a gas since t = 0.
std::vector<ObservableType> gas_types() {
  using namespace need;
  return {
      {"collision_frequency",
       "ν = 2 C/(N t): pair collisions C begun since t = 0 per particle per unit time, each counted for both "
       "partners (Enskog's ν_E = χ 4nσ²√(πkT/m) for hard spheres [Chapman1970, ch. 16])",
       need::collisions | positions, named("collision_frequency"), false,
       of_collisions([](const CollisionStatistics& s, const ParticleConfiguration& c) {
         return 2 * s.collisions / (double(c.positions.size()) * s.time);
       }), {}, {}},
      {"virial_pressure",
       "P from the virial theorem averaged since t = 0, d P V t = ∫ Σ m|v|² dt + ∫ Σ_pairs r_ij·F_ij dt (hard "
       "spheres: Σ_collisions r_ij·Δp_i) [Allen2017, ch. 2]; periodic boxes",
       need::virial | positions, named("virial_pressure"), false,
       of_collisions([](const CollisionStatistics& s, const ParticleConfiguration& c) {
         return (s.kinetic + s.virial) / (double(c.dimension) * box_volume(c) * s.time);
       }), {}, {}},
      {"compressibility_factor",
       "Z = P V/(N k T) = 1 + W/∫Σ m|v|² dt with k T = ⟨Σ m|v|²⟩/(d N) (Carnahan–Starling for hard spheres "
       "[Carnahan1969]); periodic boxes",
       need::virial | positions, named("compressibility_factor"), false,
       of_collisions([](const CollisionStatistics& s, const ParticleConfiguration&) { return 1 + s.virial / s.kinetic; }), {}, {}},
  };
}

// Final-only measures: the pair distribution profile and the oscillation of a series over observe.window.
std::vector<ObservableType> final_only_types() {
  using namespace need;
  return {
      {"pair_distribution",
       "profile r, P: P(r) = (1/N) Σ_{i≠j} 1{|X_i − X_j| <= r} at 90 radii on (2R, 20R] [Degond2024] (final only)",
       positions, named("pair_distribution"), false, {}, {},
       [](const ParticleView& v) {
         const ParticleConfiguration& c = v.configuration();
         const PairDistribution p = pair_distribution(c, pair_distribution_radii(c.radius, 90));
         return Profile{"r", "P", p.r, p.p};
       }},
      {"oscillation_period:<series>",
       "mean period of the series' oscillation over observe.window: mean spacing of its turning points of the same "
       "kind, every cycle (final only; any engine, per realization)",
       0, of_a_series("oscillation_period"), false, {}, {}, {}, oscillation(&OscillationClassification::mean_period)},
      {"oscillation_amplitude:<series>",
       "mean amplitude (half peak-to-peak) of the series' oscillation over observe.window, every cycle (final only; any "
       "engine, per realization)",
       0, of_a_series("oscillation_amplitude"), false, {}, {}, {},
       oscillation(&OscillationClassification::mean_amplitude)},
      {"oscillation_rms:<series>",
       "√2 × the standard deviation of the series over whole cycles in observe.window: the amplitude of a sine of "
       "the same variance, nearly free of the noise bias of peaks (final only; any engine, per realization)",
       0, of_a_series("oscillation_rms"), false, {}, {}, {}, oscillation(&OscillationClassification::rms_amplitude)},
      {"oscillation_mean:<series>", "mean of the series over observe.window (final only; any engine, per realization)", 0,
       of_a_series("oscillation_mean"), false, {}, {}, {},
       [](std::span<const double>, std::span<const double> x) {
         double sum = 0;
         for (double v : x) sum += v;
         return x.empty() ? nan : sum / double(x.size());
       }},
  };
}

}  // namespace

const std::vector<ObservableType>& observable_types() {
  static const std::vector<ObservableType> types = [] {
    std::vector<ObservableType> all;
    for (auto family : {density_types, cluster_types, shape_types, gas_types, final_only_types})
      for (ObservableType& type : family()) all.push_back(std::move(type));
    return all;
  }();
  return types;
}

}  // namespace aggkit

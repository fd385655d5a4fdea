// The DEM core (particle/dem/): the clipped binary collision in closed form against the integrator, the
// (e, t_c) calibration with and without `exact`, the contact duration, a two-body Kepler orbit under direct
// gravity, and results independent of the gravity thread count.
#include <catch2/catch.hpp>

#include <cmath>

#include "particle/dem/contact_law.hpp"
#include "particle/dem/dem.hpp"

using namespace aggkit;

namespace {

Box open_box() {
  Box box;
  box.dimension = 3;
  box.boundary = Boundary::open;
  return box;
}

// (e, t_c) calibration as the engine does it: k/m* = (π² + ln² e)/t_c², γ/m* = 2ζ√(k/m*).
DemSettings calibrated(double e, double contact_time, bool exact) {
  DemSettings s;
  const double rate = (M_PI * M_PI + std::log(e) * std::log(e)) / (contact_time * contact_time);
  s.stiffness_per_mass = rate;
  s.damping_per_mass = 2 * (exact ? exact_damping_ratio(e) : formula_damping_ratio(e)) * std::sqrt(rate);
  s.dt = contact_time / 50;
  return s;
}

struct Collision {
  double restitution, overlap_time;
};

// Head-on collision of spheres (R = 1, masses m1, m2) approaching at relative speed `speed`; runs until they
// separate. The initial gap puts the onset of the contact at `phase` of a step. overlap_time: steps with
// δ > 0, times dt.
Collision head_on(const DemSettings& settings, double speed, double m1 = 1, double m2 = 1, double phase = 0.37) {
  ParticleStart start;
  start.positions = {{-1.0 - (20 + phase) * speed * settings.dt, 0, 0}, {1.0, 0, 0}};
  start.velocities = {{speed * m2 / (m1 + m2), 0, 0}, {-speed * m1 / (m1 + m2), 0, 0}};
  start.radii = {1, 1};
  start.masses = {m1, m2};
  Dem dem(open_box(), start, settings);
  std::size_t overlapping = 0;
  for (int k = 0; k < 100000; ++k) {
    dem.step();
    const double gap = dem.positions()[1][0] - dem.positions()[0][0] - 2;
    if (gap < 0) ++overlapping;
    else if (overlapping > 0) break;
  }
  const double separating = dem.velocities()[1][0] - dem.velocities()[0][0];
  return {separating / speed, double(overlapping) * settings.dt};
}

}  // namespace

TEST_CASE("dem: the closed-form clipped collision", "[dem]") {
  // ζ = 0: a half period of the undamped spring, e = 1.
  CHECK(clipped_collision(0).restitution == Approx(1).margin(1e-15));
  CHECK(clipped_collision(0).overlap_time == Approx(M_PI).epsilon(1e-14));
  // Continuous across critical damping (ζ = 1: e = e^{−2}, force zero at ω0 t = 2).
  CHECK(clipped_collision(1).restitution == Approx(std::exp(-2.0)).epsilon(1e-14));
  CHECK(clipped_collision(1 - 1e-7).restitution == Approx(std::exp(-2.0)).epsilon(1e-6));
  CHECK(clipped_collision(1 + 1e-7).restitution == Approx(std::exp(-2.0)).epsilon(1e-6));
  // Monotone fall of the realised restitution with ζ.
  double previous = 1.0;
  for (double zeta = 0.05; zeta < 20; zeta *= 1.3) {
    const double e = clipped_collision(zeta).restitution;
    CHECK(e < previous);
    previous = e;
  }
  // Clipping raises the restitution above the formula's e (known effect of the clipped dashpot).
  for (double e : {0.1, 0.28, 0.5, 0.9}) {
    CHECK(clipped_collision(formula_damping_ratio(e)).restitution > e);
    CHECK(clipped_collision(exact_damping_ratio(e)).restitution == Approx(e).epsilon(1e-10));
  }
  CHECK_THROWS(exact_damping_ratio(0));
  CHECK_THROWS(exact_damping_ratio(1.5));
}

TEST_CASE("dem: a binary head-on collision returns the calibrated restitution", "[dem]") {
  // The measured error of the exact calibration at dt = t_c/50 is at most 9.1e-4 (e = 0.1) over onset phases,
  // speeds and mass ratios: second order in dt (the onset of the dashpot is integrated to second order).
  const double tc = 1e-3;
  for (double e : {0.1, 0.28, 0.5, 0.9}) {
    INFO("e = " << e);
    for (double phase : {0.0, 0.25, 0.5, 0.75}) {
      INFO("onset phase " << phase);
      CHECK(head_on(calibrated(e, tc, true), 0.01, 1, 1, phase).restitution == Approx(e).margin(1e-3));
      CHECK(head_on(calibrated(e, tc, true), 1.0, 1.0, 3.7, phase).restitution == Approx(e).margin(1e-3));
    }
    // formula: the clipped closed form's value at the formula's ζ (above e; measured within 1.3e-3 at
    // dt = t_c/50, the stiffer ω0 of small e making its step error the larger).
    const double expected = clipped_collision(formula_damping_ratio(e)).restitution;
    CHECK(head_on(calibrated(e, tc, false), 1.0).restitution == Approx(expected).margin(1.5e-3));
    CHECK(head_on(calibrated(e, tc, false), 1.0).restitution > e + 1e-3);
  }
  // Second order: four times smaller steps, at least eight times smaller error.
  DemSettings fine = calibrated(0.1, tc, true);
  const double coarse_error = std::abs(head_on(fine, 1.0).restitution - 0.1);
  fine.dt /= 4;
  CHECK(std::abs(head_on(fine, 1.0).restitution - 0.1) < coarse_error / 8);
}

TEST_CASE("dem: the contact lasts t_c", "[dem]") {
  // Without clipping the formula's stiffness gives a damped half period ω_d = π/t_c: the contact lasts t_c.
  // With clipping the spheres part when the force reaches zero and fly apart over the remaining overlap: the
  // geometric duration is the closed form's overlap_time, which tends to t_c as e → 1.
  const double tc = 2e-3;
  for (double e : {0.28, 0.5, 0.9, 0.999}) {
    INFO("e = " << e);
    const DemSettings s = calibrated(e, tc, false);
    const double omega0 = std::sqrt(s.stiffness_per_mass);
    const double expected = clipped_collision(formula_damping_ratio(e)).overlap_time / omega0;
    const Collision c = head_on(s, 1.0);
    CHECK(c.overlap_time == Approx(expected).margin(1.01 * s.dt));
    if (e >= 0.9) CHECK(c.overlap_time == Approx(tc).epsilon(0.04));
  }
  // The force-carrying part of an undamped collision is exactly t_c.
  const DemSettings elastic = calibrated(1.0, tc, false);
  CHECK(clipped_collision(0).force_time / std::sqrt(elastic.stiffness_per_mass) == Approx(tc).epsilon(1e-14));
  CHECK(head_on(elastic, 1.0).overlap_time == Approx(tc).margin(1.01 * elastic.dt));
}

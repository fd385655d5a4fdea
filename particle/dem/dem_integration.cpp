// Time integration of the DEM engine: velocity Verlet with vectorised drift and spin passes (quaternions
// integrated only with friction) and gravity on a longer step (impulse splitting).
#include "particle/dem/dem.hpp"

#include "particle/dem/direct_gravity.hpp"
#include "particle/dem/gravity_tree.hpp"

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "particle/common/simd_clones.hpp"
#include "particle/dem/dem_inline.hpp"

namespace aggkit {

namespace {

// The translational half of step()'s first pass over particles [begin, end) on flat arrays (3 doubles per
// particle): kick by F dt/2m, drift, periodic wrap by one side, the dashpot's velocity, forces cleared, and
// the Verlet list's displacement check. Branch-free, so that it vectorises; the arithmetic of each particle
// is that of the plain loop.
struct Drift {
  double *x, *v, *f, *u;
  const double *inverse_mass, *built;  // built: positions at the list's build (x itself when there are none)
  double dt, half, moved_limit;
  bool periodic;
  double side[3], half_side[3];
};
constexpr unsigned drift_moved = 1, drift_fault = 2;  // some particle beyond skin/2; a wrap by one side failed

AGGKIT_SIMD_CLONES unsigned drift_chunk(const Drift& a, std::size_t begin, std::size_t end) {
  double* const x = a.x;
  double* const v = a.v;
  double* const f = a.f;
  double* const u = a.u;
  const double* const inverse_mass = a.inverse_mass;
  const double* const built = a.built;
  const double dt = a.dt, half = a.half, limit = a.moved_limit;
  // Without periodic images the shifts are zero and the bounds infinite: the selects then do nothing.
  const bool periodic = a.periodic;
  const double inf = std::numeric_limits<double>::infinity();
  const double shift0 = periodic ? a.side[0] : 0.0, shift1 = periodic ? a.side[1] : 0.0, shift2 = periodic ? a.side[2] : 0.0;
  const double side0 = periodic ? a.side[0] : inf, side1 = periodic ? a.side[1] : inf, side2 = periodic ? a.side[2] : inf;
  const double low = periodic ? 0.0 : -inf;
  const double half0 = periodic ? a.half_side[0] : inf, half1 = periodic ? a.half_side[1] : inf, half2 = periodic ? a.half_side[2] : inf;
  int moved = 0, fault = 0;
#pragma omp simd reduction(| : moved, fault)
  for (std::size_t i = begin; i < end; ++i) {
    const double hm = half * inverse_mass[i];
    double d2 = 0;
    int bad = 0;
    // One component: shift, side, half side of its axis.
    auto component = [&](std::size_t e, double shift, double side, double half_side) {
      const double kick = hm * f[e];
      const double vk = v[e] + kick;
      v[e] = vk;
      double c = x[e] + dt * vk;
      c += c < 0 ? shift : c >= side ? -shift : 0.0;
      bad |= c >= low && c < side ? 0 : 1;
      double d = c - built[e];
      d += d > half_side ? -shift : d < -half_side ? shift : 0.0;
      d2 += d * d;
      x[e] = c;
      u[e] = vk + kick;  // the dashpot's estimate of v(t + dt): second order
      f[e] = 0;
    };
    component(3 * i, shift0, side0, half0);
    component(3 * i + 1, shift1, side1, half1);
    component(3 * i + 2, shift2, side2, half2);
    moved |= d2 > limit ? int(drift_moved) : 0;
    fault |= bad ? int(drift_fault) : 0;
  }
  return unsigned(moved | fault);
}

// The rotational half (friction): ω kicked by the torque's half step, its prediction for the tangential
// springs, torques cleared, and q ← exp(½ ω dt) q (rotation by |ω| dt about ω, space frame), renormalised.
// For a half angle a below 1e-3 (the usual case) cos a and sin(a)/|ω| from their series (next terms
// < 1e-19) and the renormalisation by one Newton step from 1 (|p|² − 1 is round-off), branch-free and
// vectorised; larger angles are left to rotate_large (cos, sin, a square root). ω = 0 leaves q as it is.
struct Spin {
  double *w, *w_pred, *torque;
  std::array<double, 4>* q;
  const double* inverse_inertia;
  double dt, half;
};

std::array<double, 4> rotated(const std::array<double, 4>& r, const std::array<double, 4>& q) {
  return {r[0] * q[0] - r[1] * q[1] - r[2] * q[2] - r[3] * q[3], r[0] * q[1] + r[1] * q[0] + r[2] * q[3] - r[3] * q[2],
          r[0] * q[2] - r[1] * q[3] + r[2] * q[0] + r[3] * q[1], r[0] * q[3] + r[1] * q[2] - r[2] * q[1] + r[3] * q[0]};
}

constexpr double small_half_angle2 = 1e-6;

AGGKIT_SIMD_CLONES bool spin_chunk(const Spin& a, std::size_t begin, std::size_t end) {
  double* const w = a.w;
  double* const w_pred = a.w_pred;
  double* const torque = a.torque;
  double* const q = a.q[0].data();
  const double* const inverse_inertia = a.inverse_inertia;
  const double dt = a.dt, half = a.half;
  int large = 0;
#pragma omp simd reduction(| : large)
  for (std::size_t i = begin; i < end; ++i) {
    const double hi = half * inverse_inertia[i];  // I = 2/5 m R²
    const std::size_t e = 3 * i;
    const double spin0 = hi * torque[e], spin1 = hi * torque[e + 1], spin2 = hi * torque[e + 2];
    const double w0 = w[e] + spin0, w1 = w[e + 1] + spin1, w2c = w[e + 2] + spin2;
    w[e] = w0, w[e + 1] = w1, w[e + 2] = w2c;
    w_pred[e] = w0 + spin0, w_pred[e + 1] = w1 + spin1, w_pred[e + 2] = w2c + spin2;
    torque[e] = 0, torque[e + 1] = 0, torque[e + 2] = 0;
    const double w2 = w0 * w0 + w1 * w1 + w2c * w2c;
    const double a2 = 0.25 * w2 * dt * dt;
    large |= int(w2 > 0) & int(a2 >= small_half_angle2);
    constexpr double c2 = 1.0 / 2, c4 = 1.0 / 24, s2 = 1.0 / 6, s4 = 1.0 / 120;  // multiplications, not divisions
    const double c = 1 - a2 * c2 + a2 * a2 * c4;
    const double sw = half * (1 - a2 * s2 + a2 * a2 * s4);  // sin(a)/|ω|
    // Otherwise (ω = 0, or a large angle left to rotate_large) r = (1, 0, 0, 0) and no renormalisation:
    // p = q exactly. Selects on values, not on the stores, so that the loop vectorises.
    const bool rotate = int(w2 > 0) & int(a2 < small_half_angle2);
    const std::size_t o = 4 * i;
    const double r0 = rotate ? c : 1.0, r1 = rotate ? sw * w0 : 0.0, r2 = rotate ? sw * w1 : 0.0, r3 = rotate ? sw * w2c : 0.0;
    const double q0 = q[o], q1 = q[o + 1], q2 = q[o + 2], q3 = q[o + 3];
    const double p0 = r0 * q0 - r1 * q1 - r2 * q2 - r3 * q3, p1 = r0 * q1 + r1 * q0 + r2 * q3 - r3 * q2,
                 p2 = r0 * q2 - r1 * q3 + r2 * q0 + r3 * q1, p3 = r0 * q3 + r1 * q2 - r2 * q1 + r3 * q0;
    const double length2 = p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3;
    const double inverse_length = rotate ? 1.5 - 0.5 * length2 : 1.0;
    q[o] = p0 * inverse_length, q[o + 1] = p1 * inverse_length, q[o + 2] = p2 * inverse_length, q[o + 3] = p3 * inverse_length;
  }
  return large != 0;
}

void rotate_large(const Spin& a, std::size_t begin, std::size_t end) {
  for (std::size_t i = begin; i < end; ++i) {
    const double wx = a.w[3 * i], wy = a.w[3 * i + 1], wz = a.w[3 * i + 2];
    const double w2 = wx * wx + wy * wy + wz * wz;
    const double a2 = 0.25 * w2 * a.dt * a.dt;
    if (!(w2 > 0) || a2 < small_half_angle2) continue;
    const double angle = std::sqrt(a2);
    const double sw = std::sin(angle) * a.half / angle;
    std::array<double, 4> p = rotated({std::cos(angle), sw * wx, sw * wy, sw * wz}, a.q[i]);
    const double inverse_length = 1 / std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3]);
    for (double& c : p) c *= inverse_length;
    a.q[i] = p;
  }
}

// The closing half kick of step(): v += F dt/2m over particles [begin, end) (flat arrays); returns Σ m|v|²
// (a vectorised sum: its order is fixed by the range).
AGGKIT_SIMD_CLONES double kick(double* v, const double* f, const double* inverse_mass, const double* mass, double half, std::size_t begin,
                               std::size_t end) {
  double sum = 0;
#pragma omp simd reduction(+ : sum)
  for (std::size_t i = begin; i < end; ++i) {
    const double h = half * inverse_mass[i];
    const std::size_t e = 3 * i;
    const double v0 = v[e] + h * f[e], v1 = v[e + 1] + h * f[e + 1], v2 = v[e + 2] + h * f[e + 2];
    v[e] = v0, v[e + 1] = v1, v[e + 2] = v2;
    sum += mass[i] * (v0 * v0 + v1 * v1 + v2 * v2);
  }
  return sum;
}

}  // namespace

void Dem::step() {
  const double dt = settings_.dt, half = 0.5 * dt;
  const std::size_t n = x_.size();
  const std::size_t substeps = settings_.gravity ? settings_.gravity_substeps : 1;
  // Impulse splitting (r-RESPA): gravity kicks by K dt/2 at both ends of every K contact steps.
  if (substeps > 1 && counters_.steps % substeps == 0)
    for (std::size_t i = 0; i < n; ++i) v_[i] = v_[i] + (0.5 * double(substeps) * dt * inverse_mass_[i]) * gravity_[i];
  // One pass: kick, drift, wrap, the dashpot's prediction, the list's displacement check, rotation, and the
  // force and torque arrays cleared for the next evaluation (the arrays are streamed once).
  // Fixed chunks of particles (their number from N only), possibly on several threads.
  const bool friction = settings_.friction > 0;
  const double skin = 0.2 * max_radius_, moved_limit = 0.25 * skin * skin;
  const std::size_t chunks = std::clamp<std::size_t>(n / 2048, 1, 64);
  std::vector<char> moved_in(chunks, 0);
  parallel(chunks, [&](std::size_t chunk) {
    const std::size_t begin = chunk * n / chunks, end = (chunk + 1) * n / chunks;
    const bool check = pairs_built_at_.size() == n;
    Drift drift{x_[0].data(), v_[0].data(), f_[0].data(), u_[0].data(), inverse_mass_.data(),
                check ? pairs_built_at_[0].data() : x_[0].data(), dt, half, moved_limit, periodic_, {}, {}};
    for (int k = 0; k < 3; ++k) drift.side[k] = side_[k], drift.half_side[k] = half_side_[k];
    const unsigned flags = drift_chunk(drift, begin, end);
    if (flags & drift_fault)  // more than a box side in one step, or −tiny + L = L: the exact wrap
      for (std::size_t i = begin; i < end; ++i) {
        Vector3& xi = x_[i];
        for (int k = 0; k < 3; ++k)
          if (!(xi[k] >= 0 && xi[k] < side_[k])) xi[k] = box_.wrap(xi)[k];
      }
    bool moved = check && (flags & drift_moved);
    if (check && (flags & drift_fault) && !moved)
      for (std::size_t i = begin; i < end && !moved; ++i) {
        Vector3 d = x_[i] - pairs_built_at_[i];
        for (int k = 0; k < 3; ++k) d[k] += d[k] > half_side_[k] ? -side_[k] : d[k] < -half_side_[k] ? side_[k] : 0.0;
        moved = dot(d, d) > moved_limit;
      }
    moved_in[chunk] = moved;
    if (!friction) return;
    Spin spin{w_[0].data(), w_pred_[0].data(), torque_[0].data(), q_.data(), inverse_inertia_.data(), dt, half};
    if (spin_chunk(spin, begin, end)) rotate_large(spin, begin, end);
  });
  moved_beyond_skin_ = std::find(moved_in.begin(), moved_in.end(), 1) != moved_in.end();
  forces_cleared_ = true;
  wall_impulse_ = wall_impulse_ - half * wall_force_;
  compute_forces();
  std::vector<double> twice_kinetic(chunks, 0.0);  // Σ m|v|² per chunk, added in chunk order
  parallel(chunks, [&](std::size_t chunk) {
    const std::size_t begin = chunk * n / chunks, end = (chunk + 1) * n / chunks;
    twice_kinetic[chunk] = kick(v_[0].data(), f_[0].data(), inverse_mass_.data(), mass_.data(), half, begin, end);
    if (friction) kick(w_[0].data(), torque_[0].data(), inverse_inertia_.data(), mass_.data(), half, begin, end);  // ω; sum unused
  });
  for (double sum : twice_kinetic) counters_.kinetic_integral += dt * sum;
  wall_impulse_ = wall_impulse_ - half * wall_force_;
  ++counters_.steps;
  if (substeps > 1 && counters_.steps % substeps == 0) {
    std::fill(gravity_.begin(), gravity_.end(), Vector3{0, 0, 0});
    gravity_forces(gravity_);
    for (std::size_t i = 0; i < n; ++i) v_[i] = v_[i] + (0.5 * double(substeps) * dt * inverse_mass_[i]) * gravity_[i];
  }
  time_ = double(counters_.steps) * dt;  // no accumulated round-off
}

}  // namespace aggkit

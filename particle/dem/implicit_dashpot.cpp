#include "particle/dem/implicit_dashpot.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace aggkit {

double dashpot_theta(double x) {
  // θ = 1/(1 − e^{−x}) − 1/x (the same fraction); its cancellation costs ~ε/x, so the series below 10^-3.
  if (x < 1e-3) return 0.5 + x / 12 - x * x * x / 720;
  return -1 / std::expm1(-x) - 1 / x;
}

namespace {

using Matrix3 = std::array<double, 6>;  // symmetric: xx, yy, zz, xy, xz, yz

Vector3 times(const Matrix3& a, const Vector3& v) {
  return {a[0] * v[0] + a[3] * v[1] + a[4] * v[2], a[3] * v[0] + a[1] * v[1] + a[5] * v[2], a[4] * v[0] + a[5] * v[1] + a[2] * v[2]};
}

Matrix3 inverse(const Matrix3& a) {
  // Cofactors of a symmetric positive definite matrix (its diagonal ≥ the particle's mass: no pivoting needed).
  const double c00 = a[1] * a[2] - a[5] * a[5], c11 = a[0] * a[2] - a[4] * a[4], c22 = a[0] * a[1] - a[3] * a[3];
  const double c01 = a[4] * a[5] - a[3] * a[2], c02 = a[3] * a[5] - a[4] * a[1], c12 = a[3] * a[4] - a[0] * a[5];
  const double det = a[0] * c00 + a[3] * c01 + a[4] * c02;
  return {c00 / det, c11 / det, c22 / det, c01 / det, c02 / det, c12 / det};
}

}  // namespace

std::vector<double> implicit_dashpot_forces(const std::vector<DashpotContact>& contacts, const std::vector<double>& masses,
                                            const std::vector<Vector3>& velocities, const std::vector<Vector3>& forces, double dt,
                                            DashpotSolve& stats) {
  const std::size_t n_contacts = contacts.size();
  std::vector<double> total(n_contacts, 0.0);
  if (n_contacts == 0) return total;
  constexpr std::uint32_t none = UINT32_MAX;
  // The particles touching a contact, numbered in order of first appearance (a fixed order).
  std::vector<std::uint32_t> local(masses.size(), none), particle;
  auto number = [&](std::uint32_t p) {
    if (p == DashpotContact::wall || local[p] != none) return;
    local[p] = std::uint32_t(particle.size());
    particle.push_back(p);
  };
  for (const DashpotContact& c : contacts) number(c.i), number(c.j);
  const std::size_t n = particle.size();
  std::vector<Vector3> start(n);  // v½
  for (std::size_t a = 0; a < n; ++a) start[a] = velocities[particle[a]];
  // Each contact's θ, its two local ends (none for a wall) and its separation speed at v½.
  std::vector<double> theta(n_contacts), start_speed(n_contacts);
  std::vector<std::uint32_t> end_i(n_contacts), end_j(n_contacts);
  auto separation_speed = [&](std::size_t c, const std::vector<Vector3>& u) {
    const Vector3 relative = end_i[c] == none ? u[end_j[c]] : u[end_j[c]] - u[end_i[c]];
    return dot(contacts[c].normal, relative);
  };
  for (std::size_t c = 0; c < n_contacts; ++c) {
    const DashpotContact& k = contacts[c];
    theta[c] = dashpot_theta(k.damping * dt / k.reduced_mass);
    end_i[c] = k.i == DashpotContact::wall ? none : local[k.i];
    end_j[c] = local[k.j];
    start_speed[c] = separation_speed(c, start);
  }
  std::vector<char> active(n_contacts, 1);
  std::vector<Vector3> b(n), v(n), r(n), z(n), p(n), q(n);
  std::vector<Matrix3> block(n), block_inverse(n);
  auto apply = [&](const std::vector<Vector3>& x, std::vector<Vector3>& y) {  // y = (M + dt Σ θγ P) x
    for (std::size_t a = 0; a < n; ++a) y[a] = masses[particle[a]] * x[a];
    for (std::size_t c = 0; c < n_contacts; ++c) {
      if (!active[c]) continue;
      const Vector3 f = (dt * theta[c] * contacts[c].damping * separation_speed(c, x)) * contacts[c].normal;
      y[end_j[c]] = y[end_j[c]] + f;
      if (end_i[c] != none) y[end_i[c]] = y[end_i[c]] - f;
    }
  };
  for (std::size_t pass = 0; pass <= n_contacts; ++pass) {
    // Right-hand side M v½ + dt (f − Σ (1 − θ) γ P v½) and the preconditioner over the active contacts; a
    // removed contact's spring leaves f.
    for (std::size_t a = 0; a < n; ++a) {
      const double m = masses[particle[a]];
      b[a] = m * start[a] + dt * forces[particle[a]];
      block[a] = {m, m, m, 0, 0, 0};
    }
    for (std::size_t c = 0; c < n_contacts; ++c) {
      const Vector3& e = contacts[c].normal;
      const double gamma = contacts[c].damping;
      const Vector3 change = (active[c] ? -dt * (1 - theta[c]) * gamma * start_speed[c] : -dt * contacts[c].spring) * e;  // on j
      b[end_j[c]] = b[end_j[c]] + change;
      if (end_i[c] != none) b[end_i[c]] = b[end_i[c]] - change;
      if (!active[c]) continue;
      const double w = dt * theta[c] * gamma;
      const Matrix3 outer{w * e[0] * e[0], w * e[1] * e[1], w * e[2] * e[2], w * e[0] * e[1], w * e[0] * e[2], w * e[1] * e[2]};
      for (std::uint32_t end : {end_i[c], end_j[c]})
        if (end != none)
          for (int k = 0; k < 6; ++k) block[end][k] += outer[k];
    }
    for (std::size_t a = 0; a < n; ++a) block_inverse[a] = inverse(block[a]);
    // Preconditioned conjugate gradients, started from v½ (an aggregate's relative velocities change little
    // in a step), then from the previous pass's solution.
    double b_norm = 0;
    for (std::size_t a = 0; a < n; ++a) {
      if (pass == 0) v[a] = start[a];
      b_norm += dot(b[a], times(block_inverse[a], b[a]));
    }
    apply(v, q);
    double rz = 0;
    for (std::size_t a = 0; a < n; ++a) {
      r[a] = b[a] - q[a];
      z[a] = times(block_inverse[a], r[a]);
      p[a] = z[a];
      rz += dot(r[a], z[a]);
    }
    ++stats.solves;
    constexpr double tolerance = 1e-12;  // relative, in the preconditioner's norm
    for (int iteration = 0; rz > tolerance * tolerance * b_norm; ++iteration) {
      if (iteration == 10000)
        throw std::runtime_error("dem: the implicit dashpot's conjugate gradients did not converge in 10^4 iterations (" +
                                 std::to_string(n) + " particles, " + std::to_string(n_contacts) + " contacts)");
      ++stats.iterations;
      apply(p, q);
      double pq = 0;
      for (std::size_t a = 0; a < n; ++a) pq += dot(p[a], q[a]);
      const double alpha = rz / pq;
      double rz_next = 0;
      for (std::size_t a = 0; a < n; ++a) {
        v[a] = v[a] + alpha * p[a];
        r[a] = r[a] - alpha * q[a];
        z[a] = times(block_inverse[a], r[a]);
        rz_next += dot(r[a], z[a]);
      }
      const double beta = rz_next / rz;
      rz = rz_next;
      for (std::size_t a = 0; a < n; ++a) p[a] = z[a] + beta * p[a];
    }
    // The dashpot force γ (θ w(v') + (1 − θ) w(v½)); contacts whose total force would attract leave the system.
    bool removed = false;
    for (std::size_t c = 0; c < n_contacts; ++c) {
      if (!active[c]) continue;
      total[c] = contacts[c].spring - contacts[c].damping * (theta[c] * separation_speed(c, v) + (1 - theta[c]) * start_speed[c]);
      if (total[c] < 0) {
        active[c] = 0;
        total[c] = 0;
        removed = true;
      }
    }
    if (!removed) break;
  }
  return total;
}

}  // namespace aggkit

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

// The linear system of one step's implicit dashpots: the particles touching a contact, numbered in order of
// first appearance (a fixed order), and per contact its θ, its two local ends (none for a wall), whether it
// is still in the system and its separation speed at v½.
struct DashpotSystem {
  static constexpr std::uint32_t none = UINT32_MAX;
  const std::vector<DashpotContact>& contacts;
  const std::vector<double>& masses;
  double dt;
  std::vector<std::uint32_t> particle;
  std::vector<double> theta, start_speed;
  std::vector<std::uint32_t> end_i, end_j;
  std::vector<char> active;

  DashpotSystem(const std::vector<DashpotContact>& k, const std::vector<double>& m, double step) : contacts(k), masses(m), dt(step) {
    std::vector<std::uint32_t> local(masses.size(), none);
    auto number = [&](std::uint32_t p) {
      if (p == DashpotContact::wall || local[p] != none) return;
      local[p] = std::uint32_t(particle.size());
      particle.push_back(p);
    };
    for (const DashpotContact& c : contacts) number(c.i), number(c.j);
    const std::size_t n_contacts = contacts.size();
    theta.resize(n_contacts);
    start_speed.resize(n_contacts);
    end_i.resize(n_contacts);
    end_j.resize(n_contacts);
    active.assign(n_contacts, 1);
    for (std::size_t c = 0; c < n_contacts; ++c) {
      const DashpotContact& d = contacts[c];
      theta[c] = dashpot_theta(d.damping * dt / d.reduced_mass);
      end_i[c] = d.i == DashpotContact::wall ? none : local[d.i];
      end_j[c] = local[d.j];
    }
  }
  double separation_speed(std::size_t c, const std::vector<Vector3>& u) const {
    const Vector3 relative = end_i[c] == none ? u[end_j[c]] : u[end_j[c]] - u[end_i[c]];
    return dot(contacts[c].normal, relative);
  }
  void apply(const std::vector<Vector3>& x, std::vector<Vector3>& y) const {  // y = (M + dt Σ θγ P) x
    for (std::size_t a = 0; a < particle.size(); ++a) y[a] = masses[particle[a]] * x[a];
    for (std::size_t c = 0; c < contacts.size(); ++c) {
      if (!active[c]) continue;
      const Vector3 f = (dt * theta[c] * contacts[c].damping * separation_speed(c, x)) * contacts[c].normal;
      y[end_j[c]] = y[end_j[c]] + f;
      if (end_i[c] != none) y[end_i[c]] = y[end_i[c]] - f;
    }
  }
  // Right-hand side M v½ + dt (f − Σ (1 − θ) γ P v½) and the block-diagonal preconditioner over the active
  // contacts (inverted); a removed contact's spring leaves f.
  void assemble(const std::vector<Vector3>& start, const std::vector<Vector3>& forces, std::vector<Vector3>& b,
                std::vector<Matrix3>& block_inverse) const {
    const std::size_t n = particle.size();
    std::vector<Matrix3> block(n);
    for (std::size_t a = 0; a < n; ++a) {
      const double m = masses[particle[a]];
      b[a] = m * start[a] + dt * forces[particle[a]];
      block[a] = {m, m, m, 0, 0, 0};
    }
    for (std::size_t c = 0; c < contacts.size(); ++c) {
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
  }
  // Preconditioned conjugate gradients for v from its value on entry.
  void solve(const std::vector<Vector3>& b, const std::vector<Matrix3>& block_inverse, std::vector<Vector3>& v,
             DashpotSolve& stats) const;
};

void DashpotSystem::solve(const std::vector<Vector3>& b, const std::vector<Matrix3>& block_inverse, std::vector<Vector3>& v,
                          DashpotSolve& stats) const {
  const std::size_t n = particle.size();
  std::vector<Vector3> r(n), z(n), p(n), q(n);
  double b_norm = 0;
  for (std::size_t a = 0; a < n; ++a) b_norm += dot(b[a], times(block_inverse[a], b[a]));
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
                               std::to_string(n) + " particles, " + std::to_string(contacts.size()) + " contacts)");
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
}

}  // namespace

std::vector<double> implicit_dashpot_forces(const std::vector<DashpotContact>& contacts, const std::vector<double>& masses,
                                            const std::vector<Vector3>& velocities, const std::vector<Vector3>& forces, double dt,
                                            DashpotSolve& stats) {
  const std::size_t n_contacts = contacts.size();
  std::vector<double> total(n_contacts, 0.0);
  if (n_contacts == 0) return total;
  DashpotSystem system(contacts, masses, dt);
  const std::size_t n = system.particle.size();
  std::vector<Vector3> start(n);  // v½
  for (std::size_t a = 0; a < n; ++a) start[a] = velocities[system.particle[a]];
  for (std::size_t c = 0; c < n_contacts; ++c) system.start_speed[c] = system.separation_speed(c, start);
  // Started from v½ (an aggregate's relative velocities change little in a step), then from the previous
  // pass's solution.
  std::vector<Vector3> b(n), v(start);
  std::vector<Matrix3> block_inverse(n);
  for (std::size_t pass = 0; pass <= n_contacts; ++pass) {
    system.assemble(start, forces, b, block_inverse);
    system.solve(b, block_inverse, v, stats);
    // The dashpot force γ (θ w(v') + (1 − θ) w(v½)); contacts whose total force would attract leave the system.
    bool removed = false;
    for (std::size_t c = 0; c < n_contacts; ++c) {
      if (!system.active[c]) continue;
      total[c] = contacts[c].spring -
                 contacts[c].damping * (system.theta[c] * system.separation_speed(c, v) + (1 - system.theta[c]) * system.start_speed[c]);
      if (total[c] < 0) {
        system.active[c] = 0;
        total[c] = 0;
        removed = true;
      }
    }
    if (!removed) break;
  }
  return total;
}

}  // namespace aggkit

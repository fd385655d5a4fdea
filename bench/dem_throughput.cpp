// DEM contact throughput (particle-steps per second) on the case compared with LAMMPS (bench/dem_vs_lammps.sh):
// N spheres of diameter 1 and mass 1 on a cubic lattice at volume fraction 0.3 in a periodic box, velocity
// components uniform in [−1, 1] (zero momentum, seed 1), Hooke contacts from e = 0.9 and t_c = 0.02
// (k_n = m*(π² + ln² e)/t_c², γ_n = −2 m* ln(e)/t_c), Coulomb friction μ = 0.5 with a tangential spring
// k_t = 2/7 k_n and history (LAMMPS: pair gran/hooke/history), dt = t_c/50, no gravity, Verlet skin 0.1.
//   bench_dem_throughput run N STEPS THREADS     ours: prints N, steps, threads, wall and CPU seconds and
//                                                particle-steps/s (wall), plus contacts and list builds
//   bench_dem_throughput lammps DIR N STEPS      writes DIR/data.dem and DIR/in.dem: the same start and law
// `run` records particle_steps_per_s and particle_steps_per_cpu_s (bench/figures.hpp).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <string>

#include "bench/figures.hpp"
#include "particle/common/box.hpp"
#include "particle/common/initial_state.hpp"
#include "particle/dem/dem.hpp"

using namespace aggkit;

namespace {

constexpr double diameter = 1.0, mass = 1.0, phi = 0.3, restitution = 0.9, contact_time = 0.02, friction = 0.5;

struct Case {
  Box box;
  ParticleStart start;
  double kn, gamma_n, dt;  // absolute k_n and γ_n for m* = m/2
};

Case make_case(std::size_t n) {
  const double radius = diameter / 2;
  const double side = box_side_for_volume_fraction(3, n, radius, phi);
  Case c{Box{3, {side, side, side}, Boundary::periodic}, {}, 0, 0, contact_time / 50};
  c.start.positions = lattice_positions(c.box, n, radius);
  c.start.velocities = initial_velocities(3, n, VelocityLaw::uniform_components, 1.0, 1);
  c.start.radii.assign(n, radius);
  c.start.masses.assign(n, mass);
  const double reduced = mass / 2, l = std::log(restitution);
  c.kn = reduced * (M_PI * M_PI + l * l) / (contact_time * contact_time);
  c.gamma_n = -2 * reduced * l / contact_time;
  return c;
}

int run(std::size_t n, std::size_t steps, std::size_t threads, const bench::Figures& figures) {
  Case c = make_case(n);
  DemSettings s;
  s.stiffness = c.kn;
  s.damping = c.gamma_n;
  s.dt = c.dt;
  s.friction = friction;
  s.force_threads = threads;
  Dem dem(c.box, std::move(c.start), s);
  const auto wall0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();
  for (std::size_t k = 0; k < steps; ++k) dem.step();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const double cpu = double(std::clock() - cpu0) / CLOCKS_PER_SEC;
  const auto& k = dem.counters();
  std::printf("ours N %zu steps %zu threads %zu wall_s %.3f cpu_s %.3f particle_steps_per_s %.4g collisions %llu list_builds %llu "
              "max_overlap %.4g clamped %llu\n",
              n, steps, threads, wall, cpu, double(n) * double(steps) / wall, (unsigned long long)k.collisions,
              (unsigned long long)k.list_builds, k.max_overlap, (unsigned long long)k.clamped_contacts);
  const std::string name = "N=" + bench::Figures::text(double(n)) + " threads=" + std::to_string(threads);
  figures.add(name, "particle_steps_per_s", double(n) * double(steps) / wall, "1/s");
  figures.add(name, "particle_steps_per_cpu_s", double(n) * double(steps) / cpu, "1/s");
  return 0;
}

int write_lammps(const std::filesystem::path& dir, std::size_t n, std::size_t steps) {
  const Case c = make_case(n);
  std::filesystem::create_directories(dir);
  std::ofstream data(dir / "data.dem");
  data.precision(17);
  data << "aggkit DEM throughput case\n\n" << n << " atoms\n1 atom types\n\n";
  for (const char* axis : {"x", "y", "z"}) data << "0 " << c.box.side[0] << " " << axis << "lo " << axis << "hi\n";
  const double density = mass / (M_PI / 6 * diameter * diameter * diameter);
  data << "\nAtoms # sphere\n\n";
  for (std::size_t i = 0; i < n; ++i)
    data << i + 1 << " 1 " << diameter << " " << density << " " << c.start.positions[i][0] << " " << c.start.positions[i][1] << " "
         << c.start.positions[i][2] << "\n";
  data << "\nVelocities\n\n";
  for (std::size_t i = 0; i < n; ++i)
    data << i + 1 << " " << c.start.velocities[i][0] << " " << c.start.velocities[i][1] << " " << c.start.velocities[i][2] << " 0 0 0\n";
  // LAMMPS' Hooke law: F_n = k_n δ − m_eff γ_n v_n, F_t = −k_t Δs − m_eff γ_t v_t truncated at μ F_n
  // (γ_t = 0: our tangential spring has no dashpot).
  std::ofstream in(dir / "in.dem");
  in.precision(17);
  in << "units lj\natom_style sphere\ndimension 3\nboundary p p p\ncomm_modify vel yes\nread_data data.dem\n"
     << "pair_style gran/hooke/history " << c.kn << " " << 2.0 / 7.0 * c.kn << " " << c.gamma_n / (mass / 2) << " 0.0 " << friction
     << " 1\npair_coeff * *\nneighbor 0.1 bin\nneigh_modify delay 0 every 1 check yes\ntimestep " << c.dt
     << "\nfix 1 all nve/sphere\nthermo " << steps << "\nrun " << steps << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "run" && argc == 5)
    return run(std::size_t(std::atof(argv[2])), std::size_t(std::atof(argv[3])), std::size_t(std::atoi(argv[4])),
               bench::Figures("dem_throughput", argc, argv));
  if (mode == "lammps" && argc == 5) return write_lammps(argv[2], std::size_t(std::atof(argv[3])), std::size_t(std::atof(argv[4])));
  std::fprintf(stderr, "usage: %s run N STEPS THREADS | lammps DIR N STEPS\n", argv[0]);
  return 2;
}

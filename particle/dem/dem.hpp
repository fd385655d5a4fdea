#pragma once
// A 3-D soft-sphere DEM with optional self-gravity [Trivino2025]: spheres of independent radius R_i and
// mass m_i, linear spring–dashpot normal contacts clipped at zero (contact_law.hpp) with the overlap in the
// spring clamped at δ_max = 0.05 R_min (each clamped contact-step counted), direct pairwise gravity
// G m_i m_j / (r² + ε²) along the pair [Trivino2025, eq. 1] or a Barnes–Hut tree, velocity Verlet, contact
// search by a Verlet list (skin 0.2 R_max) built on a cell grid, and periodic, reflecting (spring–dashpot
// walls, the wall as an infinite mass) or open boundaries.
// The dashpot of step n+1 sees the predicted velocity v(n+½) + (dt/2) F(n)/m (second order): the half-step
// velocity alone lags by dt/2. The dashpot's jump at the onset of a contact is integrated to second order
// (dem_contacts.cpp: the first sample's weight); at walls it is not (first order in dt). That explicit dashpot is
// stable only while x = γ_n dt/m* < 1 (it reverses an overdamped approach beyond); when some pair's x exceeds
// `implicit_dashpot_above` (and there is no friction) every dashpot is integrated implicitly instead
// (implicit_dashpot.hpp: unconditionally stable, exact relaxation e^{−x} of a pair, second order for small x).
// Friction (μ > 0): Coulomb with a tangential spring k_t = 2/7 k_n (default) and a history per contact,
// created and dropped with the contact, rotated into the current tangent plane (length kept) and truncated
// at μ F_n; torques about lever arms R − δ/2 (they add up to the centre distance, so the angular momentum is
// kept), rotation by velocity Verlet half-kicks of ω (I = 2/5 m R²) and unit quaternions. Without friction
// rotation is not integrated. Walls are frictionless (the spring–dashpot normal force only).
// `force_threads` run the integration, the contact forces and the gravity of one step: the integration over
// fixed chunks of particles, the contacts over fixed chunks of the Verlet list into per-chunk buffers added
// to the particles in pair order, direct gravity over a fixed tiling of the pairs reduced in a fixed order
// (direct_gravity.hpp), the Barnes–Hut tree (gravity_tree.hpp) per particle: the result does not depend on
// the thread count. All of them run on one worker pool (particle/common/worker_pool.hpp) kept for the run.
// The integration's loops are vectorised (particle/common/simd_clones.hpp).
#include <cstddef>
#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "particle/common/box.hpp"
#include "particle/common/particle_start.hpp"
#include "particle/common/vector3.hpp"
#include "particle/common/worker_pool.hpp"
#include "particle/dem/implicit_dashpot.hpp"

namespace aggkit {

class StateWriter;
class StateReader;

struct DemSettings {
  // Pair law: k_n = stiffness_per_mass · m* + stiffness, γ_n = damping_per_mass · m* + damping (one of the
  // two forms used; the (e, t_c) calibration gives the per-mass rates, (stiffness, damping) the absolute).
  double stiffness_per_mass = 0, damping_per_mass = 0;
  double stiffness = 0, damping = 0;
  double dt = 0;                      // > 0
  double overlap_limit = 0.05;        // δ_max / R_min
  double contact_tolerance = 0.01;    // contact graph: r < R_i + R_j + contact_tolerance · R_min
  bool gravity = false;
  double G = 1;
  double softening = -1;              // ε; < 0: 1e-3 R_min
  double friction = 0;                // Coulomb μ; > 0: tangential springs with history, rotation
  double tangential_stiffness_ratio = 2.0 / 7.0;  // k_t / k_n
  bool tree = false;                  // Barnes–Hut (gravity_tree.hpp) instead of the direct sum
  double opening_angle = 0.5;         // θ of the tree
  // Impulse splitting (r-RESPA): gravity evaluated every K steps and applied as kicks of K dt/2 at both
  // ends of each K contact steps; between those ends the velocities lack the second gravity half-kick.
  std::size_t gravity_substeps = 1;
  std::size_t force_threads = 1;
  // The dashpots are integrated implicitly (implicit_dashpot.hpp) when the largest γ_n dt/m* over the pairs
  // (and walls) exceeds this and friction is off; explicitly otherwise. 0: always implicit; +∞: never.
  double implicit_dashpot_above = 0.2;
};

// The dashpot rule: whether Dem integrates the dashpots implicitly for these settings and the lightest
// particle's mass: the largest γ_n dt/m* of a pair (m* ≥ m_min/2) or a wall (m* = m_i ≥ m_min) exceeds
// settings.implicit_dashpot_above, and there is no friction.
bool implicit_dashpot_wanted(const DemSettings& settings, double lightest_mass);

struct DemCounters {
  std::uint64_t steps = 0;
  std::uint64_t collisions = 0;       // pairs that start to overlap (δ > 0) having not overlapped the step before
  std::uint64_t clamped_contacts = 0; // contact-steps with δ > δ_max
  double max_overlap = 0;             // largest δ seen, / R_min
  std::uint64_t list_builds = 0;      // Verlet-list rebuilds
  std::uint64_t rebounds = 0;         // contact episodes (below) that ended after an overlap
  double max_friction_ratio = 0;      // largest |F_t| / (μ F_n) over contact-steps with F_n > 0 (≤ 1)
  // Time integrals since the start, each force evaluation of a step weighted by dt (the Verlet kicks'
  // weights): the contact virial ∫ Σ_contacts r_ij · F_ij dt (r_ij = x_i − x_j, F_ij the force of j on i: the
  // normal force |F_n| r; tangential forces are normal to r_ij) and ∫ Σ_i m_i |v_i|² dt (at the step ends).
  double virial_integral = 0;
  double kinetic_integral = 0;
  std::uint64_t dashpot_solves = 0, dashpot_iterations = 0;  // implicit dashpot: linear solves, CG iterations
};

class Dem {
 public:
  // Throws std::invalid_argument for a 2-D box, non-positive radii or masses, dt <= 0, sizes that differ,
  // or gravity in a periodic box (which would need Ewald sums).
  Dem(const Box& box, ParticleStart start, const DemSettings& settings);

  void step();                        // one velocity-Verlet step of dt
  double time() const { return time_; }
  std::size_t size() const { return x_.size(); }

  const std::vector<Vector3>& positions() const { return x_; }
  const std::vector<Vector3>& velocities() const { return v_; }
  const std::vector<double>& radii() const { return radius_; }
  const std::vector<double>& masses() const { return mass_; }
  const Box& box() const { return box_; }
  const DemSettings& settings() const { return settings_; }
  const DemCounters& counters() const { return counters_; }
  bool implicit_dashpot() const { return implicit_dashpot_; }  // see DemSettings::implicit_dashpot_above
  double min_radius() const { return min_radius_; }

  Vector3 momentum() const;
  Vector3 angular_momentum() const;   // Σ m x × v + I ω about the origin
  const std::vector<Vector3>& angular_velocities() const { return w_; }
  const std::vector<std::array<double, 4>>& orientations() const { return q_; }  // unit quaternions (w, x, y, z)
  Vector3 wall_impulse() const { return wall_impulse_; }
  double kinetic_energy() const;      // translational and rotational
  // Gravitational energy of the force law: U(r) = −(G m_i m_j / ε)(π/2 − atan(r/ε)) per pair (0 without gravity).
  double gravitational_energy() const;
  // Elastic energy of the springs (clamped spring: linear beyond δ_max), pairs and walls, and the
  // tangential springs ½ k_t |ξ|².
  double elastic_energy() const;
  double total_energy() const { return kinetic_energy() + gravitational_energy() + elastic_energy(); }

  // Pair parameters for reduced mass m*.
  double pair_stiffness(double reduced_mass) const { return settings_.stiffness_per_mass * reduced_mass + settings_.stiffness; }
  double pair_damping(double reduced_mass) const { return settings_.damping_per_mass * reduced_mass + settings_.damping; }

  // Connected components of the contact graph (r < R_i + R_j + tolerance, minimum image when periodic),
  // labels 0..C−1 in order of first particle; from the last force evaluation.
  std::vector<std::uint32_t> cluster_labels() const;
  // Adhesive fraction: a contact episode is a pair staying within the contact graph's distance
  // (r < R_i + R_j + tolerance) from step to step; an episode with an overlap (δ > 0) is a collision; it is
  // adhesive when the pair has not separated again (left that distance) by now, a rebound when it has.
  // Fraction = open episodes with an overlap / (those + rebounds); NaN before any collision. Pairs that
  // bounce within the tolerance without leaving it count once.
  double adhesive_fraction() const;
  // Mass of the largest component / total mass, from the last force evaluation (computed when asked).
  double largest_cluster_mass_fraction() const;
  // largest_cluster_mass_fraction() >= fraction, answered without the components when the contact graph has
  // too few edges for any component to hold that much mass (the usual case in a gas).
  bool largest_cluster_reaches(double fraction) const;

  // Checkpoints (particle/common/checkpoint.hpp): everything step() carries from step to step — positions,
  // velocities, forces, angular state, the Verlet list with its contact states and tangential histories, the
  // clock and the counters. restore() into a Dem built from the same start and settings continues to the
  // same bits; CheckpointError if the state is of another size.
  void save(StateWriter& out) const;
  void restore(StateReader& in);

 private:
  // The Verlet list: pairs (i < j) within 2 R_max + tolerance + skin at its build, sorted by (i, j), each
  // with the state of its contact carried from step to step and across rebuilds (no per-contact lookups).
  enum PairState : std::uint8_t {
    in_graph = 1,            // r < R_i + R_j + tolerance at the last evaluation
    overlapping = 2,         // δ > 0 at the last evaluation
    episode_overlapped = 4,  // the contact episode (in_graph from step to step) has overlapped
  };
  struct PairList {
    std::vector<std::uint32_t> first, second;
    std::vector<std::uint8_t> state;
    std::vector<Vector3> history;  // tangential displacement (friction), zero unless overlapping
    std::size_t size() const { return first.size(); }
  };
  // What the pair loop adds up (per range of pairs, so that ranges can be summed in a fixed order).
  struct ContactTotals {
    std::uint64_t collisions = 0, rebounds = 0, clamped = 0, graph_edges = 0;
    double max_overlap = 0, max_friction_ratio = 0, virial = 0;
  };

  // One contact's forces as a chunk of the pair loop leaves them (added to the particles in pair order).
  struct ContactForce {
    std::uint32_t i, j;
    Vector3 normal_force;  // on j (−it on i)
    Vector3 tangential, torque_i, torque_j;  // friction: tangential force on i (−it on j), torques
    double virial;
    double dashpot;  // implicit dashpot: γ_n (times the onset weight), its force not yet in normal_force; else 0
  };

  void compute_forces();
  void contact_forces();
  void integrate_dashpots();  // implicit dashpot: the dashpots' forces from implicit_dashpot_forces()
  void rebuild_pairs();
  ContactTotals pair_forces(std::size_t begin, std::size_t end, std::vector<ContactForce>& contacts);
  // job(k) for k < jobs, on the worker pool when force_threads > 1.
  template <class Job> void parallel(std::size_t jobs, Job&& job);
  void wall_forces();
  void gravity_forces(std::vector<Vector3>& out);  // adds the gravity forces to `out`
  void tangential_force(std::uint32_t i, std::uint32_t j, Vector3& xi, const Vector3& normal, double overlap, double normal_force,
                        double normal_stiffness, ContactTotals& totals, ContactForce& out) const;
  // visit(part, i, j) for every pair i < j within `range` (and some farther), found by a cell grid in up to
  // `parts` slabs, on the worker pool when parts > 1: a part's pairs come in a fixed order, the parts' calls
  // may interleave.
  template <class Visit> void for_each_near_pair(double range, std::size_t parts, Visit&& visit) const;
  Vector3 separation(std::size_t i, std::size_t j) const;  // x_j − x_i (minimum image)
  std::vector<std::uint32_t> component_parents() const;    // union–find of the contact graph, roots = smallest index

  Box box_;
  bool periodic_ = false;
  Vector3 side_{0, 0, 0}, half_side_{0, 0, 0};
  DemSettings settings_;
  std::vector<Vector3> x_, v_, f_;
  std::vector<Vector3> gravity_;  // gravity forces at the last outer step (impulse splitting)
  std::vector<Vector3> u_;  // velocities the dashpot sees: v(t) at the start, then v(t+dt/2) + dt/2 · F(t)/m
  std::vector<double> radius_, mass_, inverse_mass_, inverse_inertia_;
  std::vector<double> heaviest_first_;  // prefix sums of the masses sorted in decreasing order
  double min_radius_ = 0, max_radius_ = 0, softening_ = 0, time_ = 0;
  Vector3 wall_impulse_{0, 0, 0};
  Vector3 wall_force_{0, 0, 0};
  DemCounters counters_;
  std::vector<Vector3> w_, w_pred_, torque_;                   // angular velocity, its prediction, torque
  std::vector<std::array<double, 4>> q_;                       // orientations
  PairList pairs_;
  std::vector<Vector3> pairs_built_at_;  // positions at the list's build
  std::uint64_t graph_edges_ = 0;        // in_graph pairs at the last evaluation
  bool first_evaluation_ = false;
  bool moved_beyond_skin_ = false;  // some particle moved more than skin/2 since the list's build (step())
  bool forces_cleared_ = false;     // step() has zeroed f_ and torque_ for the next evaluation
  std::vector<std::vector<ContactForce>> contact_buffers_;  // per chunk of the pair loop
  std::unique_ptr<WorkerPool> pool_;                        // force_threads > 1
  bool implicit_dashpot_ = false;
  std::vector<DashpotContact> wall_dashpots_;  // implicit dashpot: the walls' contacts of this evaluation
};

}  // namespace aggkit

#pragma once
// Aggregation kernels K_ij (collision rate of sizes i and j) and their separable (low-rank) forms.
// Ballistic kernel K_ij = (i^{1/3}+j^{1/3})^2 sqrt(1/i+1/j) [Kalinov2022, eq. 2]; brownian kernel
// (i/j)^a + (j/i)^a of the oscillation regimes [Kalinov2022, Sec. 5.2]; 2-D ballistic kernel
// (i^{1/2}+j^{1/2}) sqrt(1/i+1/j) of compact discs [Carnevale1990; BrilliantovPoschel2004] (derivation at
// Kernel::ballistic2d).
#include <cstddef>
#include <functional>
#include <memory>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "solvers/separable_form.hpp"

namespace aggkit {

class Kernel {
 public:
  using Function = std::function<double(double i, double j)>;

  static Kernel constant();                          // K = 1
  static Kernel sum();                               // K = i + j
  static Kernel product();                           // K = i j
  static Kernel linear(double A, double B);          // K = 1 + A(i+j) + B i j
  static Kernel generalized_product(double mu);      // K = (i j)^mu
  static Kernel ballistic();                         // K = (i^{1/3}+j^{1/3})^2 sqrt(1/i + 1/j)
  static Kernel brownian(double a);                  // K = (i/j)^a + (j/i)^a, 0 <= a <= 1
  // K = (i^{1/2}+j^{1/2}) sqrt(1/i + 1/j): ballistic aggregation of compact discs in 2-D. Clusters of k
  // monomers (mass m_k = k m, radius R_k = R k^{1/2}, area ∝ mass) with Maxwellian velocities at one
  // temperature T collide, per unit area and time, at n_i n_j · 2(R_i + R_j) · <|v_i − v_j|> (the sweep
  // width of a disc pair is twice the contact distance); v_i − v_j is a 2-D Gaussian of variance T/μ_ij per
  // component (μ_ij = m_i m_j/(m_i + m_j)), whose mean length is sqrt(π T / (2 μ_ij)) (Rayleigh). So
  // K_ij^phys = R sqrt(2π T/m) (i^{1/2}+j^{1/2}) sqrt(1/i+1/j) = K0 · K_ij, and the kinetic time of a unit
  // monomer density is τ = n_1(0) K0 t [Carnevale1990; TrizacHansen1996; BrilliantovPoschel2004, ch. 3 (the
  // 2-D collision frequency 2σ n sqrt(πT/m) of equal discs of diameter σ is K_11 n)].
  static Kernel ballistic2d();
  // A user kernel (symmetric, positive); it has no exact factorisation and is approximated like ballistic.
  static Kernel user(std::string name, Function k);

  // Builds a kernel from its scene name and parameters (kernel_registry()); throws InputError naming the
  // bad key.
  static Kernel from_name(const std::string& name, const std::map<std::string, double>& parameters);
  static std::vector<std::string> names();  // the registry's, in order

  double operator()(std::size_t i, std::size_t j) const { return function_(double(i), double(j)); }
  double at(double x, double y) const { return function_(x, y); }  // at any sizes (pivots of a graded grid)
  const std::string& name() const { return name_; }
  const std::map<std::string, double>& parameters() const { return parameters_; }
  std::string describe() const;  // e.g. "brownian(a=0.95)"
  bool has_exact_factorisation() const { return static_cast<bool>(exact_form_); }
  // K(x, y) = Σ_pq coupling[p][q] φ_p(x) φ_q(y) at any sizes (the pivots of a graded grid), where the
  // kernel has an exact factorisation; nullptr where it has none.
  struct Factors {
    std::vector<std::function<double(double)>> features;  // φ_p
    std::vector<std::vector<double>> coupling;            // P × P, symmetric
  };
  const Factors* exact_factors() const { return exact_factors_.get(); }

  // The separable form on sizes 1..N: exact where one exists, else a low-rank approximation
  // (adaptive cross approximation, never forming the N×N matrix for large N) whose maximum relative
  // entry error is about `tolerance`; the measured error is reported in the result.
  SeparableForm separable_form(std::size_t N, double tolerance = 1e-12) const;

 private:
  Kernel(std::string name, std::map<std::string, double> parameters, Function f);
  std::string name_;
  std::map<std::string, double> parameters_;
  Function function_;
  // Exact factorisation: its factors, and the builder that fills features/coupling for sizes 1..N.
  void set_exact(std::vector<std::function<double(double)>> features, std::vector<std::vector<double>> coupling);
  std::shared_ptr<const Factors> exact_factors_;
  std::function<SeparableForm(std::size_t N)> exact_form_;
};

// The named kernels, declared once: the scene parser (Kernel::from_name), its error messages, `aggkit
// kernels` and Python's aggkit.kernels() all read this list.
struct KernelParameter {
  std::string name;
  std::string allowed;             // e.g. "0 <= a <= 1"
  std::optional<double> fallback;  // none: the kernel needs it
};
struct KernelEntry {
  std::string name;
  std::string formula;
  std::vector<KernelParameter> parameters;
  std::function<Kernel(const std::map<std::string, double>& values)> make;  // every parameter present
  std::vector<std::string> parameter_names() const;
};
const std::vector<KernelEntry>& kernel_registry();
const KernelEntry* find_kernel_entry(std::string_view name);  // nullptr if unknown

}  // namespace aggkit

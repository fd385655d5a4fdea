#pragma once
// Exact solutions of pure aggregation (λ = 0) from the monodisperse start n_k(0) = δ_k1
// ([Leyvraz2003, Sec. 2]):
//   constant K = 1:  n_k = 4/(t+2)^2 (t/(t+2))^{k-1}
//   sum K = i + j:   n_k = (1-τ)(kτ)^{k-1} e^{-kτ}/k!,  τ = 1 - e^{-t}
//   product K = ij:  n_k = (kt)^{k-1} e^{-kt}/(k k!),   t < 1 (gelation at t = 1)
#include <cstddef>
#include <string>
#include <vector>

namespace aggkit {

// True if `kernel_name` has an exact solution here.
bool has_exact_solution(const std::string& kernel_name);
// n_k(t) of the untruncated system.
double exact_density(const std::string& kernel_name, std::size_t k, double t);
// M_p(t) = Σ_{k≥1} k^p n_k of the untruncated system: closed forms for p = 0, 1, 2, otherwise the series
// summed until its terms are below 1e-17 of the sum. Throws std::domain_error past gelation.
double exact_moment(const std::string& kernel_name, double p, double t);
std::vector<double> exact_distribution(const std::string& kernel_name, std::size_t N, double t);

// K_ij = 2 with shattering rate λ from a unit monodisperse start, untruncated: the monomer gain and loss
// terms cancel in the total density, dM0/dt = 2λ M0 − (1 + 2λ) M0², a logistic towards N* = 2λ/(1+2λ):
// M0(t) = N* / (1 + (N* − 1) e^{−2λt}). At λ = 0 it is 1/(1 + t).
std::vector<double> exact_total_density_k2(double lambda, const std::vector<double>& times);
double exact_total_density_k2(double lambda, double t);

}  // namespace aggkit

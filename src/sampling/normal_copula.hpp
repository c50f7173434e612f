// Correlated inputs through a normal copula (docs/rare_events.md,
// section 2): a sample's independent uniforms u of the correlated inputs are
// mapped to standard normals z = Phi^-1(u), correlated as z' = L z with
// L L^T = R (R: the copula's correlation matrix), and mapped back,
// u' = Phi(z'). Every input then keeps its own distribution (its quantile
// function is applied to u' as before) while the pairs get the asked
// dependence. Inputs outside every correlation keep their uniforms bit for
// bit, and so does the first input of each correlated set (L's first row is
// e_1), which therefore also keeps a design's stratification.
#pragma once

#include <Eigen/Core>

#include <span>
#include <vector>

namespace treedyn::sampling {

// [[ensemble.correlation]]: two inputs drawn through a normal copula with
// parameter rho (their Spearman correlation is (6 / pi) asin(rho / 2)).
struct InputCorrelation {
  unsigned a = 0, b = 0;       // input dimensions, a < b
  double normal_copula = 0.0;  // rho
  bool given_as_spearman = false;
};

// Spearman's rank correlation of a normal copula with parameter rho, and
// the parameter that gives Spearman's r: rho = 2 sin(pi r / 6).
double spearman_of_normal_copula(double rho);
double normal_copula_of_spearman(double r);

class NormalCopula {
 public:
  NormalCopula() = default;
  // Throws std::invalid_argument when R is not positive definite.
  NormalCopula(unsigned dimensions, std::span<const InputCorrelation> correlations);

  bool empty() const { return inputs_.empty(); }
  // Maps one sample's independent uniforms (all D of them) in place.
  void correlate(std::span<double> u) const;
  // The inverse in normal space: standard normals z' of all D inputs, as
  // Phi^-1 of the correlated uniforms, back to the independent z = L^-1 z'
  // (only the correlated inputs change).
  void decorrelate(std::span<double> z) const;

 private:
  std::vector<unsigned> inputs_;  // the correlated input dimensions, ascending
  Eigen::MatrixXd lower_;         // L of R restricted to inputs_
};

}  // namespace treedyn::sampling

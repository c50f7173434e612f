#include "sampling/normal_copula.hpp"

#include <Eigen/Cholesky>
#include <boost/math/distributions/normal.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace treedyn::sampling {

double spearman_of_normal_copula(double rho) { return 6.0 / std::numbers::pi * std::asin(rho / 2.0); }
double normal_copula_of_spearman(double r) { return 2.0 * std::sin(std::numbers::pi / 6.0 * r); }

NormalCopula::NormalCopula(unsigned dimensions, std::span<const InputCorrelation> correlations) {
  for (const InputCorrelation& c : correlations) {
    if (c.a >= dimensions || c.b >= dimensions || c.a == c.b)
      throw std::invalid_argument("normal copula: a correlation names an input that is not there");
    inputs_.push_back(c.a);
    inputs_.push_back(c.b);
  }
  std::sort(inputs_.begin(), inputs_.end());
  inputs_.erase(std::unique(inputs_.begin(), inputs_.end()), inputs_.end());
  const auto n = static_cast<Eigen::Index>(inputs_.size());
  Eigen::MatrixXd r = Eigen::MatrixXd::Identity(n, n);
  auto at = [this](unsigned d) {
    return static_cast<Eigen::Index>(std::lower_bound(inputs_.begin(), inputs_.end(), d) - inputs_.begin());
  };
  for (const InputCorrelation& c : correlations) r(at(c.a), at(c.b)) = r(at(c.b), at(c.a)) = c.normal_copula;
  const Eigen::LLT<Eigen::MatrixXd> llt(r);
  if (llt.info() != Eigen::Success)
    throw std::invalid_argument("normal copula: the correlation matrix is not positive definite");
  lower_ = llt.matrixL();
}

void NormalCopula::correlate(std::span<double> u) const {
  const boost::math::normal standard;
  const auto n = static_cast<Eigen::Index>(inputs_.size());
  Eigen::VectorXd z(n);  // a few doubles per sample, so that correlate() is safe on any thread
  for (Eigen::Index k = 0; k < n; ++k) z[k] = boost::math::quantile(standard, u[inputs_[static_cast<std::size_t>(k)]]);
  for (Eigen::Index k = 0; k < n; ++k) {
    const bool unit_row = lower_.row(k).head(k).isZero(0.0);
    if (unit_row) continue;  // z'_k = z_k: the uniform keeps its bits
    const double correlated = lower_.row(k).head(k + 1).dot(z.head(k + 1));
    // Phi rounds to 1 beyond z = 8.3: keep u' inside (0, 1), where every
    // quantile function is finite.
    u[inputs_[static_cast<std::size_t>(k)]] =
        std::clamp(boost::math::cdf(standard, correlated), 0x1p-1000, 1.0 - 0x1p-53);
  }
}

void NormalCopula::decorrelate(std::span<double> z) const {
  const auto n = static_cast<Eigen::Index>(inputs_.size());
  Eigen::VectorXd correlated(n);
  for (Eigen::Index k = 0; k < n; ++k) correlated[k] = z[inputs_[static_cast<std::size_t>(k)]];
  const Eigen::VectorXd independent = lower_.triangularView<Eigen::Lower>().solve(correlated);
  for (Eigen::Index k = 0; k < n; ++k) z[inputs_[static_cast<std::size_t>(k)]] = independent[k];
}

}  // namespace treedyn::sampling

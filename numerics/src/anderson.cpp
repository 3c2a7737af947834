#include "rheosim/numerics/anderson.hpp"

#include <stdexcept>

namespace rheosim::numerics {

AndersonMixer::AndersonMixer(int depth) : depth_(static_cast<std::size_t>(depth)) {
  if (depth < 0) throw std::invalid_argument("AndersonMixer: depth must be >= 0");
}

Eigen::VectorXd AndersonMixer::next(const Eigen::VectorXd& y, const Eigen::VectorXd& g, double relaxation) {
  const Eigen::VectorXd f = g - y;
  if (have_previous_ && depth_ > 0) {
    residual_steps_.push_back(f - previous_f_);
    map_steps_.push_back(g - previous_g_);
    if (residual_steps_.size() > depth_) {
      residual_steps_.erase(residual_steps_.begin());
      map_steps_.erase(map_steps_.begin());
    }
  }
  previous_f_ = f;
  previous_g_ = g;
  have_previous_ = true;
  if (residual_steps_.empty()) return y + relaxation * f;
  const auto m = static_cast<Eigen::Index>(residual_steps_.size());
  Eigen::MatrixXd dF(f.size(), m), dG(f.size(), m);
  for (Eigen::Index j = 0; j < m; ++j) {
    dF.col(j) = residual_steps_[static_cast<std::size_t>(j)];
    dG.col(j) = map_steps_[static_cast<std::size_t>(j)];
  }
  const Eigen::VectorXd gamma = dF.colPivHouseholderQr().solve(f);
  const Eigen::VectorXd y_bar = y - (dG - dF) * gamma;
  const Eigen::VectorXd f_bar = f - dF * gamma;
  return y_bar + relaxation * f_bar;
}

void AndersonMixer::reset() {
  residual_steps_.clear();
  map_steps_.clear();
  have_previous_ = false;
}

}  // namespace rheosim::numerics

#pragma once
// Anderson acceleration (type II; Walker & Ni, SIAM J. Numer. Anal. 49, 2011) of a fixed-point
// map y ↦ G(y): the next iterate combines the last `depth` iterates so that the linearised
// residual G(y) − y is least-squares smallest. Picard iterations for strongly shear-thinning laws
// converge linearly and slowly; mixing cuts the iteration count several-fold. depth 0 is plain
// (relaxed) Picard.
#include <cstddef>
#include <vector>

#include <Eigen/Dense>

namespace rheosim::numerics {

class AndersonMixer {
 public:
  explicit AndersonMixer(int depth);

  // The next iterate from the current one, y, and its image g = G(y); relaxation in (0, 1]
  // damps the step (1: the mixed image itself).
  [[nodiscard]] Eigen::VectorXd next(const Eigen::VectorXd& y, const Eigen::VectorXd& g, double relaxation);
  // Forgets the history (after a bad extrapolation).
  void reset();

 private:
  std::size_t depth_;
  std::vector<Eigen::VectorXd> residual_steps_, map_steps_;
  Eigen::VectorXd previous_f_, previous_g_;
  bool have_previous_ = false;
};

}  // namespace rheosim::numerics

#pragma once
// Gauss–Legendre quadrature: the N-point rule on [-1, 1] is exact for polynomials of degree
// 2N − 1. The 3-point rule integrates μ r³ over a fluid cell face; the 8-point rule the plate
// torque and normal force over a flow curve.
#include <array>
#include <cstddef>

namespace rheosim::numerics {

template <std::size_t N>
struct GaussLegendre;

template <>
struct GaussLegendre<3> {
  static constexpr std::array<double, 3> nodes{-0.7745966692414834, 0.0, 0.7745966692414834};
  static constexpr std::array<double, 3> weights{5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
};

template <>
struct GaussLegendre<8> {
  static constexpr std::array<double, 8> nodes{-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                               -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                               0.7966664774136267,  0.9602898564975363};
  static constexpr std::array<double, 8> weights{0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                                 0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                                 0.2223810344533745, 0.1012285362903763};
};

// ∫_a^b f with the N-point rule.
template <std::size_t N, class F>
double integrate_gauss_legendre(double a, double b, const F& f) {
  using Rule = GaussLegendre<N>;
  double sum = 0.0;
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  for (std::size_t i = 0; i < N; ++i) sum += Rule::weights[i] * f(mid + half * Rule::nodes[i]);
  return half * sum;
}

}  // namespace rheosim::numerics

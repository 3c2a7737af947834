#pragma once
// 8-point Gauss–Legendre quadrature on [a, b] (exact for polynomials to degree 15): the
// integrals of the plate torque and normal force over a local flow curve.
#include <array>
#include <cstddef>

namespace rheosim::rheometer {

template <class F>
double integrate_gauss_legendre_8(double a, double b, const F& f) {
  constexpr std::array<double, 8> nodes{-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                        -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                        0.7966664774136267,  0.9602898564975363};
  constexpr std::array<double, 8> weights{0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                          0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                          0.2223810344533745, 0.1012285362903763};
  double sum = 0.0;
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  for (std::size_t i = 0; i < nodes.size(); ++i) sum += weights[i] * f(mid + half * nodes[i]);
  return half * sum;
}

}  // namespace rheosim::rheometer

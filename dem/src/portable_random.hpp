#pragma once
// Portable random numbers for the scene (private to dem/): std::mt19937_64 is specified bit for
// bit, the std distributions are not, so the conversions to doubles are our own. A seed then
// gives the same particles with any standard library and on every MPI rank.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>

namespace rheosim::dem::detail {

class PortableRandom {
 public:
  explicit PortableRandom(std::uint64_t seed) : engine_(seed) {}
  double uniform() { return static_cast<double>(engine_() >> 11U) * 0x1.0p-53; }  // [0, 1)
  double symmetric() { return 2.0 * uniform() - 1.0; }                            // [-1, 1)
  std::size_t below(std::size_t n) {  // [0, n), n >= 1; rejection keeps it unbiased
    const std::uint64_t limit = std::numeric_limits<std::uint64_t>::max() -
                                std::numeric_limits<std::uint64_t>::max() % static_cast<std::uint64_t>(n);
    std::uint64_t x = 0;
    do x = engine_();
    while (x >= limit);
    return static_cast<std::size_t>(x % n);
  }
  // Standard normal deviate (Box–Muller; the partner value is discarded for simplicity).
  double normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
  }
  // A unit vector of uniformly distributed direction (three normal deviates, normalised).
  std::array<double, 3> direction() {
    std::array<double, 3> v{};
    double norm = 0.0;
    do {
      for (auto& c : v) c = normal();
      norm = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (norm < 1e-12);
    for (auto& c : v) c /= norm;
    return v;
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace rheosim::dem::detail

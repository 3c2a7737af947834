// Viscosity and its derivative over a span of 1e6 shear rates, for every law in the registry,
// through the array forms a solver uses (one virtual call per array).
//   build/bin/bench_rheology --benchmark_filter=viscosity/
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "rheosim/core/config.hpp"
#include "rheosim/core/rheology.hpp"

namespace {

using rheosim::core::Rheology;

// One realistic parameter set per law, keyed by its YAML name.
constexpr const char* models_yaml = R"(
newtonian:        {model: newtonian, viscosity: 1.0e-3}
power_law:        {model: power_law, consistency: 0.5, index: 0.6}
bingham:          {model: bingham, plastic_viscosity: 0.01, yield_stress: 1.0, regularization: 1000}
casson:           {model: casson, plastic_viscosity: 0.01, yield_stress: 1.0, regularization: 1000}
herschel_bulkley: {model: herschel_bulkley, consistency: 0.5, index: 0.6, yield_stress: 1.0}
carreau_yasuda:   {model: carreau_yasuda, zero_shear_viscosity: 1.0, infinite_shear_viscosity: 1.0e-3,
                   time_constant: 0.5, a: 2, n: 0.4}
cross:            {model: cross, zero_shear_viscosity: 1.0, infinite_shear_viscosity: 1.0e-3,
                   time_constant: 0.5, exponent: 0.7}
)";

constexpr std::size_t span_size = 1'000'000;

// Log-spaced shear rates over 1e-3..1e4 1/s, the range a rheometer or cavity flow sees.
std::vector<double> shear_rates() {
  std::vector<double> rates(span_size);
  for (std::size_t i = 0; i < span_size; ++i)
    rates[i] = std::pow(10.0, -3.0 + 7.0 * static_cast<double>(i) / static_cast<double>(span_size - 1));
  return rates;
}

void viscosity(benchmark::State& state, const Rheology& law, std::span<const double> rates) {
  std::vector<double> mu(rates.size());
  for (auto _ : state) {
    law.viscosity(rates, mu);
    benchmark::DoNotOptimize(mu.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rates.size()));
}

void viscosity_derivative(benchmark::State& state, const Rheology& law, std::span<const double> rates) {
  std::vector<double> dmu(rates.size());
  for (auto _ : state) {
    law.viscosity_derivative(rates, dmu);
    benchmark::DoNotOptimize(dmu.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rates.size()));
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;

  static const std::vector<double> rates = shear_rates();
  const auto document = rheosim::core::Document::from_string(models_yaml, "bench_rheology.yaml");
  // Every registered law must have a parameter set above: a missing one is an error here.
  for (const std::string& name : rheosim::core::builtin_rheologies().names()) {
    const auto law = rheosim::core::make_rheology(document.root().section({name, "parameters of one law", "-"}));
    // The lambdas share the law and the static rates instead of copying 8 MB per benchmark.
    benchmark::RegisterBenchmark(("viscosity/" + name).c_str(), [law](benchmark::State& state) {
      viscosity(state, *law, rates);
    })->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("viscosity_derivative/" + name).c_str(), [law](benchmark::State& state) {
      viscosity_derivative(state, *law, rates);
    })->Unit(benchmark::kMillisecond);
  }
  document.check_all_keys_known();

  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

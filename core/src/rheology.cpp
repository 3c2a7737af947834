#include "rheosim/core/rheology.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "rheology/bingham.hpp"
#include "rheology/carreau_yasuda.hpp"
#include "rheology/casson.hpp"
#include "rheology/cross.hpp"
#include "rheology/herschel_bulkley.hpp"
#include "rheology/newtonian.hpp"
#include "rheology/power_law.hpp"

namespace rheosim::core {

void check_equal_sizes(std::size_t a, std::size_t b) {
  if (a != b)
    throw std::invalid_argument(
        fmt::format("rheology array form: {} shear rates but an output array of size {}", a, b));
}

// The one list of built-in laws; a new law is added here and nowhere else.
void add_builtin_rheologies(RheologyRegistry& registry) {
  add<Newtonian>(registry);
  add<PowerLaw>(registry);
  add<Bingham>(registry);
  add<Casson>(registry);
  add<HerschelBulkley>(registry);
  add<CarreauYasuda>(registry);
  add<Cross>(registry);
}

const RheologyRegistry& builtin_rheologies() { return builtin_registry<Rheology, add_builtin_rheologies>(); }

std::shared_ptr<const Rheology> make_rheology(const Section& section) { return builtin_rheologies().make(section); }

}  // namespace rheosim::core

#pragma once
// Run-time selection of physics models by their YAML name (cf. LAMMPS styles, OpenFOAM
// run-time selection). One explicit list per interface fills it (see add_builtin_*), so no
// model is lost to the linker dropping unreferenced static initialisers.
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rheosim/core/config.hpp"

namespace rheosim::core {

template <class Base>
class Registry {
 public:
  using Maker = std::function<std::unique_ptr<Base>(const Section&)>;

  void add(std::string name, Maker make) {
    if (!makers_.try_emplace(name, std::move(make)).second) throw std::logic_error("model registered twice: " + name);
  }

  // Builds the model named by the section's `model` key from that section.
  [[nodiscard]] std::unique_ptr<Base> make(const Section& section) const {
    const std::string name = section.choice({"model", "model name", "-"}, names());
    return makers_.at(name)(section);
  }

  [[nodiscard]] bool contains(std::string_view name) const { return makers_.find(name) != makers_.end(); }

  [[nodiscard]] std::vector<std::string> names() const {
    std::vector<std::string> out;
    out.reserve(makers_.size());
    for (const auto& [name, maker] : makers_) out.push_back(name);
    return out;  // std::map keeps them sorted
  }

 private:
  std::map<std::string, Maker, std::less<>> makers_;
};

// Registers Model under Model::name; Model::Params::from(section) parses and validates.
template <class Model, class Base>
void add(Registry<Base>& registry) {
  registry.add(std::string(Model::name), [](const Section& s) -> std::unique_ptr<Base> {
    return std::make_unique<Model>(Model::Params::from(s));
  });
}

}  // namespace rheosim::core

#pragma once
// Run-time selection of physics models by their YAML name (cf. LAMMPS styles, OpenFOAM
// run-time selection). One explicit list per interface fills it (see add_builtin_*), so no
// model is lost to the linker dropping unreferenced static initialisers.
//
// A model is built from its part of a case file (make(section): the `model` key names it, the
// model's Params::from reads the rest), or, for a model without settings, by name alone
// (make(name)), which is how code that chose a model as an enum builds it: no case-file text is
// made up and parsed for it.
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "rheosim/core/config.hpp"

namespace rheosim::core {

template <class Base>
class Registry {
 public:
  using Maker = std::function<std::unique_ptr<Base>(const Section&)>;
  using DefaultMaker = std::function<std::unique_ptr<Base>()>;

  // without_settings: builds the model when it has no settings (empty: it needs a section).
  void add(std::string name, Maker make, DefaultMaker without_settings = {}) {
    if (!entries_.try_emplace(name, Entry{std::move(make), std::move(without_settings)}).second)
      throw std::logic_error("model registered twice: " + name);
  }

  // Builds the model named by the section's `model` key from that section.
  [[nodiscard]] std::unique_ptr<Base> make(const Section& section) const {
    const std::string name = section.choice({"model", "model name", "-"}, names());
    return entries_.at(name).make(section);
  }

  // Builds a model that has no settings by its name; std::invalid_argument names the valid ones.
  [[nodiscard]] std::unique_ptr<Base> make(std::string_view name) const {
    const auto it = entries_.find(name);
    if (it == entries_.end()) {
      std::string valid;
      for (const auto& n : names()) valid += (valid.empty() ? "" : ", ") + n;
      throw std::invalid_argument("unknown model '" + std::string(name) + "' (valid: " + valid + ")");
    }
    if (!it->second.without_settings)
      throw std::invalid_argument("model '" + std::string(name) +
                                  "' has settings: build it from its case-file section");
    return it->second.without_settings();
  }

  [[nodiscard]] bool contains(std::string_view name) const { return entries_.find(name) != entries_.end(); }

  [[nodiscard]] std::vector<std::string> names() const {
    std::vector<std::string> out;
    out.reserve(entries_.size());
    for (const auto& [name, entry] : entries_) out.push_back(name);
    return out;  // std::map keeps them sorted
  }

 private:
  struct Entry {
    Maker make;
    DefaultMaker without_settings;
  };
  std::map<std::string, Entry, std::less<>> entries_;
};

// The built-in models of one interface: AddBuiltins fills the registry once (thread-safe static
// initialisation) and it is only read afterwards; each interface's builtin_* returns it.
template <class Base, void (*AddBuiltins)(Registry<Base>&)>
[[nodiscard]] const Registry<Base>& builtin_registry() {
  static const Registry<Base> registry = [] {
    Registry<Base> r;
    AddBuiltins(r);
    return r;
  }();
  return registry;
}

// Registers Model under Model::name; Model::Params::from(section) parses and validates. A model
// whose Params are empty has no settings and can also be built by name.
template <class Model, class Base>
void add(Registry<Base>& registry) {
  typename Registry<Base>::DefaultMaker without_settings;
  if constexpr (std::is_empty_v<typename Model::Params>)
    without_settings = []() -> std::unique_ptr<Base> { return std::make_unique<Model>(typename Model::Params{}); };
  registry.add(
      std::string(Model::name),
      [](const Section& s) -> std::unique_ptr<Base> { return std::make_unique<Model>(Model::Params::from(s)); },
      std::move(without_settings));
}

}  // namespace rheosim::core

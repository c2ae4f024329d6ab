#pragma once
/// Components of one kind by name: the one mechanism behind every kind (PHYs,
/// MACs, channel stages, sample stages, position sources, mobility models).
///
/// A component is a struct with `config::ComponentInfo info` (its kind, name,
/// settings and doc) and the factories of its kind. Built-in components are
/// listed by the build: each folder declares itself with CMake's
/// `rfsitl_component()`, which generates the list that registers them the
/// first time the kind's registry is used. Plugins loaded from a directory at
/// start (plugin_loader.hpp) add theirs through the same add().
///
/// Threads: registration happens at start, on one thread, before any run
/// (built-ins on first use, then plugins); afterwards every reader may read
/// from any thread. References returned stay valid for the process's life.
#include <algorithm>
#include <deque>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace rfsitl::registry {

template <class Component>
class Registry {
 public:
  using List = std::vector<std::reference_wrapper<const Component>>;
  /// A kind's own rule for its components (a PHY must declare its largest
  /// payload); throws std::invalid_argument naming what is wrong.
  using Check = std::function<void(const Component&)>;

  explicit Registry(Check check = {}) : check_(std::move(check)) {}

  /// Adds `c` under c.info.name. Throws std::invalid_argument when the name is
  /// empty or taken (a plugin cannot replace a built-in, nor two plugins each
  /// other: which would win would depend on the order of a folder listing),
  /// or when the kind's check refuses it.
  void add(Component c) {
    const std::string name = c.info.name;
    if (name.empty()) throw std::invalid_argument(c.info.kind + " component without a name");
    if (find(name) != nullptr) {
      throw std::invalid_argument(c.info.kind + " '" + name + "' is registered already");
    }
    if (check_) check_(c);
    const Component& stored = store_.emplace_back(std::move(c));
    const auto at =
        std::lower_bound(sorted_.begin(), sorted_.end(), name,
                         [](const Component& a, const std::string& n) { return a.info.name < n; });
    sorted_.insert(at, std::cref(stored));
  }

  /// Every component, sorted by name.
  const List& all() const { return sorted_; }

  /// The component named `name`, or nullptr.
  const Component* find(std::string_view name) const {
    const auto at = std::lower_bound(
        sorted_.begin(), sorted_.end(), name,
        [](const Component& a, std::string_view n) { return std::string_view(a.info.name) < n; });
    return at != sorted_.end() && at->get().info.name == name ? &at->get() : nullptr;
  }

  /// The names, sorted.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    out.reserve(sorted_.size());
    for (const Component& c : sorted_) out.push_back(c.info.name);
    return out;
  }

 private:
  Check check_;
  std::deque<Component> store_;  // a deque: adding never moves what is stored
  List sorted_;
};

/// A registry of `Component`'s kind holding its built-ins: calls the kind's
/// generated `register_builtin(Registry<Component>&)`, found by argument-
/// dependent lookup in the kind's namespace. For the kind's accessor, which
/// keeps the one instance.
template <class Component>
Registry<Component> with_builtins(typename Registry<Component>::Check check = {}) {
  Registry<Component> r(std::move(check));
  register_builtin(r);
  return r;
}

}  // namespace rfsitl::registry

#pragma once
/// A component's settings declared once, as the fields of its own settings
/// struct (GNU Radio 4's annotated fields are the model):
///
///   const config::Fields<GfskSettings>& fields() {
///     static const auto f = config::Fields<GfskSettings>()
///         .integer("samples_per_symbol", &GfskSettings::samples_per_symbol, "samples",
///                  2, 32, "samples per symbol; the air rate is fs / this")
///         .real("bandwidth_time", &GfskSettings::bandwidth_time, "", {0.2, 1.0}, "...");
///     return f;
///   }
///
/// The default is the struct's own member initializer. A list setting's items
/// are declared the same way (record_fields.hpp). From this come the
/// declarations (ComponentInfo), and build() turns checked Settings into the struct.
#include <concepts>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "rfsitl/config/component_info.hpp"
#include "rfsitl/config/record_fields.hpp"

namespace rfsitl::config {

template <typename T>
class Fields {
 public:
  template <std::unsigned_integral M>
  Fields& integer(std::string name, M T::*member, std::string unit, std::uint64_t lo,
                  std::uint64_t hi, std::string doc) {
    Setting s = declare(std::move(name), ValueType::kInteger, std::uint64_t{defaults_.*member},
                        std::move(unit), std::move(doc));
    s.range = Range{static_cast<double>(lo), static_cast<double>(hi)};
    return add(
        std::move(s),
        [member](T& t, const Value& v) { t.*member = static_cast<M>(std::get<std::uint64_t>(v)); },
        [member](const T& t) { return Value(std::uint64_t{t.*member}); });
  }

  /// An integer that must be one of `allowed` (e.g. the 802.11a rates).
  template <std::unsigned_integral M>
  Fields& integer_choice(std::string name, M T::*member, std::string unit,
                         const std::vector<std::uint64_t>& allowed, std::string doc) {
    Setting s = declare(std::move(name), ValueType::kInteger, std::uint64_t{defaults_.*member},
                        std::move(unit), std::move(doc));
    for (const std::uint64_t a : allowed) s.choices.push_back(std::to_string(a));
    return add(
        std::move(s),
        [member](T& t, const Value& v) { t.*member = static_cast<M>(std::get<std::uint64_t>(v)); },
        [member](const T& t) { return Value(std::uint64_t{t.*member}); });
  }

  template <std::floating_point M>
  Fields& real(std::string name, M T::*member, std::string unit, Range range, std::string doc) {
    Setting s = declare(std::move(name), ValueType::kReal, static_cast<double>(defaults_.*member),
                        std::move(unit), std::move(doc));
    s.range = range;
    return add(
        std::move(s),
        [member](T& t, const Value& v) { t.*member = static_cast<M>(std::get<double>(v)); },
        [member](const T& t) { return Value(static_cast<double>(t.*member)); });
  }

  Fields& flag(std::string name, bool T::*member, std::string doc) {
    return add(
        declare(std::move(name), ValueType::kBool, defaults_.*member, "", std::move(doc)),
        [member](T& t, const Value& v) { t.*member = std::get<bool>(v); },
        [member](const T& t) { return Value(t.*member); });
  }

  /// Free text; a rule() says what is acceptable.
  Fields& text(std::string name, std::string T::*member, std::string doc) {
    return add(
        declare(std::move(name), ValueType::kText, defaults_.*member, "", std::move(doc)),
        [member](T& t, const Value& v) { t.*member = std::get<std::string>(v); },
        [member](const T& t) { return Value(t.*member); });
  }

  /// One of a list of names, stored as the name.
  Fields& choice(std::string name, std::string T::*member, std::vector<std::string> options,
                 std::string doc) {
    Setting s = declare(std::move(name), ValueType::kText, defaults_.*member, "", std::move(doc));
    s.choices = std::move(options);
    return add(
        std::move(s), [member](T& t, const Value& v) { t.*member = std::get<std::string>(v); },
        [member](const T& t) { return Value(t.*member); });
  }

  /// One of a list of names, stored as the enumerator each names.
  template <typename E>
  requires std::is_enum_v<E> Fields& choice(std::string name, E T::*member,
                                            std::vector<std::pair<std::string, E>> options,
                                            std::string doc) {
    std::string initial;
    for (const auto& [word, e] : options) {
      if (e == defaults_.*member) initial = word;
    }
    Setting s = declare(std::move(name), ValueType::kText, initial, "", std::move(doc));
    for (const auto& o : options) s.choices.push_back(o.first);
    return add(
        std::move(s),
        [member, options](T& t, const Value& v) {
          for (const auto& [word, e] : options) {
            if (word == std::get<std::string>(v)) t.*member = e;
          }
        },
        [member, options](const T& t) {
          for (const auto& [word, e] : options) {
            if (e == t.*member) return Value(word);
          }
          return Value(std::string());
        });
  }

  /// A list of records (waypoints, channel taps): `items` declares what each
  /// holds, bound to the members of E; the list holds min_items..max_items.
  /// The default is the member's initializer (usually empty).
  template <typename E>
  Fields& records(std::string name, std::vector<E> T::*member, const RecordFields<E>& items,
                  std::size_t min_items, std::size_t max_items, std::string doc) {
    Setting s = declare(std::move(name), ValueType::kRecords, items.records(defaults_.*member), "",
                        std::move(doc));
    s.items = items.shape(min_items, max_items);
    return add(
        std::move(s),
        [member, items](T& t, const Value& v) { t.*member = items.build(std::get<Records>(v)); },
        [member, items](const T& t) { return Value(items.records(t.*member)); });
  }

  /// A rule across fields, run on the built struct after every value passed its
  /// own limits. Throws SettingError naming the key at fault.
  Fields& rule(std::function<void(const T&)> check) {
    rules_.push_back(std::move(check));
    return *this;
  }

  /// The struct with every declared field set from `s`; fields `s` lacks keep
  /// their defaults. Precondition: `s` passed info().validate().
  T build(const Settings& s) const {
    T t = defaults_;
    for (std::size_t i = 0; i < decls_.size(); ++i) {
      if (const Value* v = s.find(decls_[i].name)) apply_[i](t, *v);
    }
    return t;
  }

  /// Every declared field of `t` as Settings (build()'s inverse).
  Settings settings_of(const T& t) const {
    Settings s;
    for (std::size_t i = 0; i < decls_.size(); ++i) s.set(decls_[i].name, read_[i](t));
    return s;
  }

  /// The component's self-description, its checks included.
  ComponentInfo info(std::string kind, std::string name, std::string doc) const {
    ComponentInfo c{std::move(kind), std::move(name), std::move(doc), decls_, {}};
    if (!rules_.empty()) {
      c.check = [self = std::make_shared<const Fields>(*this)](const Settings& s) {
        const T t = self->build(s);
        for (const auto& r : self->rules_) r(t);
      };
    }
    return c;
  }

 private:
  static Setting declare(std::string name, ValueType type, Value initial, std::string unit,
                         std::string doc) {
    Setting s;
    s.name = std::move(name);
    s.type = type;
    s.default_value = std::move(initial);
    s.unit = std::move(unit);
    s.doc = std::move(doc);
    return s;
  }

  Fields& add(Setting s, std::function<void(T&, const Value&)> apply,
              std::function<Value(const T&)> read) {
    decls_.push_back(std::move(s));
    apply_.push_back(std::move(apply));
    read_.push_back(std::move(read));
    return *this;
  }

  T defaults_{};
  std::vector<Setting> decls_;
  std::vector<std::function<void(T&, const Value&)>> apply_;
  std::vector<std::function<Value(const T&)>> read_;
  std::vector<std::function<void(const T&)>> rules_;
};

}  // namespace rfsitl::config

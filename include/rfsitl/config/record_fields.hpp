#pragma once
/// The items of a list setting declared once, as the fields of an item struct
/// (as fields.hpp does for a component's settings):
///
///   struct Tap { double delay_ns = 0; double gain_db = 0; };
///   const auto taps = config::RecordFields<Tap>()
///       .required("delay_ns", &Tap::delay_ns, "ns", {0, 1e6}, "delay after the first path")
///       .required("gain_db", &Tap::gain_db, "dB", {-200, 0}, "power relative to the first");
///   config::Fields<Stage>().records("taps", &Stage::taps, taps, 1, 64, "the paths");
///
/// A `double` member the item may leave out keeps its initializer (the field's
/// default); a `std::optional<double>` member stays empty, and the owner's
/// rule says what that means.
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rfsitl/config/record.hpp"

namespace rfsitl::config {

template <typename E>
class RecordFields {
 public:
  /// A field an item may leave out; then the member keeps its initializer.
  RecordFields& real(std::string name, double E::*member, std::string unit, Range range,
                     std::string doc) {
    RecordField f{std::move(name), std::move(unit), range, std::move(doc), defaults_.*member};
    return add(
        std::move(f), [member](E& e, double v) { e.*member = v; },
        [member](const E& e) { return std::optional<double>(e.*member); });
  }

  /// A field an item may leave out; then the member stays empty.
  RecordFields& real(std::string name, std::optional<double> E::*member, std::string unit,
                     Range range, std::string doc) {
    RecordField f{std::move(name), std::move(unit), range, std::move(doc), std::nullopt};
    return add(
        std::move(f), [member](E& e, double v) { e.*member = v; },
        [member](const E& e) { return e.*member; });
  }

  /// A field every item must give.
  RecordFields& required(std::string name, double E::*member, std::string unit, Range range,
                         std::string doc) {
    RecordField f{std::move(name), std::move(unit), range, std::move(doc), std::nullopt, true};
    return add(
        std::move(f), [member](E& e, double v) { e.*member = v; },
        [member](const E& e) { return std::optional<double>(e.*member); });
  }

  /// The declarations, with the item count allowed.
  RecordShape shape(std::size_t min_items, std::size_t max_items) const {
    return RecordShape{decls_, min_items, max_items};
  }

  /// The items as structs, every declared field an item gives set; the others
  /// keep their initializers. Precondition: the items passed shape().rejection().
  std::vector<E> build(const Records& items) const {
    std::vector<E> out;
    out.reserve(items.size());
    for (const Record& r : items) {
      E e = defaults_;
      for (std::size_t i = 0; i < decls_.size(); ++i) {
        if (const double* v = r.find(decls_[i].name)) apply_[i](e, *v);
      }
      out.push_back(std::move(e));
    }
    return out;
  }

  /// The structs as items (a default list in a settings struct becomes the
  /// setting's default value), in declaration order.
  Records records(const std::vector<E>& items) const {
    Records out;
    for (const E& e : items) {
      Record r;
      for (std::size_t i = 0; i < decls_.size(); ++i) {
        if (const auto v = read_[i](e)) r.set(decls_[i].name, *v);
      }
      out.push_back(std::move(r));
    }
    return out;
  }

 private:
  RecordFields& add(RecordField f, std::function<void(E&, double)> apply,
                    std::function<std::optional<double>(const E&)> read) {
    decls_.push_back(std::move(f));
    apply_.push_back(std::move(apply));
    read_.push_back(std::move(read));
    return *this;
  }

  E defaults_{};
  std::vector<RecordField> decls_;
  std::vector<std::function<void(E&, double)>> apply_;
  std::vector<std::function<std::optional<double>(const E&)>> read_;
};

}  // namespace rfsitl::config

#pragma once
// One schema, three walkers: every settings struct describes its fields once through
// `visit(Visitor&)`, and the YAML loader, the printer and the checker all walk that
// description. A field therefore cannot be loaded without also having a unit, a default
// (the struct member's initialiser) and a valid range.

#include <array>
#include <cstddef>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace vigs::config {

/// What the schema says about one field. Ranges are inclusive.
struct FieldInfo {
  std::string_view unit;  ///< SI unit or "-" for dimensionless / enumerations.
  double min = 0.0;
  double max = 0.0;
  std::string_view doc;
};

/// Allowed values of a string field; empty means any string. A view: the names outlive the
/// call (a braced list at the call site, or an enumeration's name table).
class Choices {
 public:
  Choices(std::initializer_list<std::string_view> names) : names_(names.begin(), names.size()) {}
  template <std::size_t N>
  Choices(const std::array<std::string_view, N>& names) : names_(names) {}

  [[nodiscard]] std::size_t size() const { return names_.size(); }
  [[nodiscard]] auto begin() const { return names_.begin(); }
  [[nodiscard]] auto end() const { return names_.end(); }

 private:
  std::span<const std::string_view> names_;
};

class Visitor {
 public:
  virtual ~Visitor() = default;

  virtual void field(std::string_view key, double& value, const FieldInfo& info) = 0;
  virtual void field(std::string_view key, int& value, const FieldInfo& info) = 0;
  virtual void field(std::string_view key, bool& value, std::string_view doc) = 0;
  virtual void field(std::string_view key, std::string& value, Choices choices,
                     std::string_view doc) = 0;
  /// Fixed-length numeric vector (e.g. a translation, or a 3x3 matrix in row order).
  virtual void field(std::string_view key, double* values, int count, const FieldInfo& info) = 0;

  template <std::size_t N>
  void field(std::string_view key, std::array<double, N>& values, const FieldInfo& info) {
    field(key, values.data(), static_cast<int>(N), info);
  }

  /// Enumeration written as one of its names; names[i] names the enumerator of value i.
  template <class Enum, std::size_t N>
  requires std::is_enum_v<Enum>
  void field(std::string_view key, Enum& value, const std::array<std::string_view, N>& names,
             std::string_view doc) {
    const auto index = static_cast<std::size_t>(value);
    std::string text(index < N ? names[index] : std::string_view{});
    field(key, text, Choices(names), doc);
    for (std::size_t i = 0; i < N; ++i) {
      if (names[i] == text) value = static_cast<Enum>(i);
    }
  }

  /// Nested mapping. `body` visits the section's fields.
  template <class Settings>
  void section(std::string_view key, Settings& settings) {
    if (enter(key)) {
      settings.visit(*this);
      leave();
    }
  }

  /// Cross-field rule (e.g. "rotation must be orthonormal"). The loader reports a failed
  /// check against `key`; printers ignore it.
  virtual void require(bool ok, std::string_view key, std::string_view message) = 0;

 protected:
  virtual bool enter(std::string_view key) = 0;
  virtual void leave() = 0;
};

}  // namespace vigs::config

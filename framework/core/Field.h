#pragma once
// Typed fields: the one place where a scene attribute is declared (name,
// default, unit, range, help) and parsed. The same declaration drives the XML
// loader, `--set` overrides, `trephine components` and the generated reference.
//
//   Field<double> d_stiffness{this, "stiffness", 2.0,
//                             {.help = "Spring stiffness k", .unit = "N/mm", .min = 0.0}};
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/Diagnostics.h"
#include "framework/math/Math.h"

namespace trephine {

class FieldOwner;

struct FieldInfo {
  std::string_view help;
  std::string_view unit = "";
  bool required = false;
  // Inclusive limits for numbers, list elements and vector components.
  std::optional<double> min = std::nullopt;
  std::optional<double> max = std::nullopt;
  // When true, `min` itself is not allowed (a rate or a radius must be > 0).
  bool minExclusive = false;
  // Links only: the link is followed during initialisation only (to subscribe
  // to a channel, to aim a path), never while ticking, so it may join
  // components of different rate groups.
  bool initOnly = false;
};

// What a value's text may refer to: the directory of the file that set it.
struct ParseContext {
  std::filesystem::path baseDirectory;
};

class BaseField {
 public:
  BaseField(FieldOwner* owner, std::string_view name, FieldInfo info);
  BaseField(const BaseField&) = delete;
  BaseField& operator=(const BaseField&) = delete;
  virtual ~BaseField() = default;

  const std::string& name() const { return m_name; }
  const FieldInfo& info() const { return m_info; }
  FieldOwner& owner() const { return *m_owner; }

  virtual std::string typeName() const = 0;     // as shown in the reference: "double", "vec3", ...
  virtual std::string valueText() const = 0;    // current value as scene text
  virtual std::string defaultText() const = 0;  // default as scene text ("" when none)
  virtual std::string rangeText() const;        // "[0, inf)", "one of: a, b" or ""
  virtual bool isLink() const { return false; }

  // Parses and validates `text`. Returns the reason it was rejected (what was
  // expected) or nothing; on success the field remembers where it was set.
  std::optional<std::string> assign(std::string_view text, const ParseContext& context, const SourceLocation& where);

  bool isSet() const { return m_isSet; }
  // Where the value came from; the owner's location when never set.
  const SourceLocation& location() const;

 protected:
  virtual std::optional<std::string> parseAndStore(std::string_view text, const ParseContext& context) = 0;
  std::optional<std::string> checkRange(double value) const;

 private:
  FieldOwner* m_owner;
  std::string m_name;
  FieldInfo m_info;
  bool m_isSet = false;
  SourceLocation m_location;
};

// Parsing and formatting of one value type. Specialised for each supported T.
template <class T>
struct FieldTraits;

template <>
struct FieldTraits<bool> {
  static std::string typeName() { return "bool"; }
  static std::optional<std::string> parse(std::string_view text, bool& out);
  static std::string format(bool value);
};
template <>
struct FieldTraits<int> {
  static std::string typeName() { return "int"; }
  static std::optional<std::string> parse(std::string_view text, int& out);
  static std::string format(int value);
};
template <>
struct FieldTraits<double> {
  static std::string typeName() { return "double"; }
  static std::optional<std::string> parse(std::string_view text, double& out);
  static std::string format(double value);
};
template <>
struct FieldTraits<std::string> {
  static std::string typeName() { return "string"; }
  static std::optional<std::string> parse(std::string_view text, std::string& out);
  static std::string format(const std::string& value) { return value; }
};
template <>
struct FieldTraits<Vec3> {
  static std::string typeName() { return "vec3"; }
  static std::optional<std::string> parse(std::string_view text, Vec3& out);
  static std::string format(const Vec3& value);
};
template <>
struct FieldTraits<std::vector<double>> {
  static std::string typeName() { return "list<double>"; }
  static std::optional<std::string> parse(std::string_view text, std::vector<double>& out);
  static std::string format(const std::vector<double>& value);
};

template <class T>
class Field : public BaseField {
 public:
  using Validator = std::function<std::optional<std::string>(const T&)>;

  Field(FieldOwner* owner, std::string_view name, T defaultValue, FieldInfo info)
      : BaseField(owner, name, info), m_default(defaultValue), m_value(std::move(defaultValue)) {}

  const T& value() const { return m_value; }
  const T& operator*() const { return m_value; }
  const T* operator->() const { return &m_value; }
  // Programmatic assignment (tests, tools); the scene path goes through assign().
  void setValue(T value) { m_value = std::move(value); }

  // An extra rule on the parsed value, e.g. "must be a unit vector".
  void setValidator(Validator validator) { m_validator = std::move(validator); }

  std::string typeName() const override { return FieldTraits<T>::typeName(); }
  std::string valueText() const override { return FieldTraits<T>::format(m_value); }
  std::string defaultText() const override { return FieldTraits<T>::format(m_default); }

 protected:
  std::optional<std::string> parseAndStore(std::string_view text, const ParseContext&) override {
    T parsed{};
    if (auto error = FieldTraits<T>::parse(text, parsed)) return error;
    if (auto error = checkValue(parsed)) return error;
    if (m_validator) {
      if (auto error = m_validator(parsed)) return error;
    }
    m_value = std::move(parsed);
    return std::nullopt;
  }

 private:
  std::optional<std::string> checkValue(const T& v) const {
    if constexpr (std::is_same_v<T, int> || std::is_same_v<T, double>) {
      return checkRange(static_cast<double>(v));
    } else if constexpr (std::is_same_v<T, Vec3>) {
      for (int i = 0; i < 3; ++i)
        if (auto e = checkRange(v[i])) return e;
    } else if constexpr (std::is_same_v<T, std::vector<double>>) {
      for (double x : v)
        if (auto e = checkRange(x)) return e;
    }
    return std::nullopt;
  }

  T m_default;
  T m_value;
  Validator m_validator;
};

// A rate in Hz (> 0). A component with a rate field ticks in the rate group of that rate.
class RateField final : public Field<double> {
 public:
  RateField(FieldOwner* owner, double defaultHz, std::string_view help = "Tick rate of this component");
  std::string typeName() const override { return "rate"; }
  // The component's rate group beside its rate (the `group` field, declared
  // with the rate): components of one rate and one group share a thread.
  const std::string& group() const { return m_group.value(); }

 private:
  Field<std::string> m_group;
};

// One of a fixed set of words.
class EnumField final : public BaseField {
 public:
  EnumField(FieldOwner* owner, std::string_view name, std::vector<std::string> options, std::string defaultValue,
            FieldInfo info);
  const std::string& value() const { return m_options[m_index]; }
  size_t index() const { return m_index; }
  bool is(std::string_view option) const { return value() == option; }
  const std::vector<std::string>& options() const { return m_options; }

  std::string typeName() const override { return "enum"; }
  std::string valueText() const override { return value(); }
  std::string defaultText() const override { return m_options[m_defaultIndex]; }
  std::string rangeText() const override;

 protected:
  std::optional<std::string> parseAndStore(std::string_view text, const ParseContext&) override;

 private:
  std::vector<std::string> m_options;
  size_t m_index = 0;
  size_t m_defaultIndex = 0;
};

// A file path, resolved relative to the directory of the scene file that set it.
// A value of the form "scheme:..." names a generated source instead (for
// example "phantom:skull?voxel=1.0") when the scheme is one the field accepts.
class FilePathField final : public BaseField {
 public:
  // Input: an existing file. InputOrDirectory: an existing file or directory
  // (a DICOM series), the directory optionally followed by "?key=value"
  // (kept in path(), for the reader). Output: any path.
  enum class Role { Input, Output, InputOrDirectory };
  FilePathField(FieldOwner* owner, std::string_view name, FieldInfo info, Role role = Role::Input,
                std::vector<std::string> schemes = {});

  const std::string& text() const { return m_text; }
  const std::filesystem::path& path() const { return m_resolved; }  // empty for a scheme
  bool isScheme() const { return !m_scheme.empty(); }
  const std::string& scheme() const { return m_scheme; }
  std::string_view schemeBody() const;  // text after "scheme:"
  bool empty() const { return m_text.empty(); }

  std::string typeName() const override { return "file"; }
  std::string valueText() const override { return m_text; }
  std::string defaultText() const override { return ""; }
  std::string rangeText() const override;

 protected:
  std::optional<std::string> parseAndStore(std::string_view text, const ParseContext& context) override;

 private:
  Role m_role;
  std::vector<std::string> m_schemes;
  std::string m_text;
  std::string m_scheme;
  std::filesystem::path m_resolved;
};

}  // namespace trephine

#include "framework/core/Field.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

#include "framework/core/FieldOwner.h"
#include "framework/core/Strings.h"

namespace trephine {

// ---- FieldOwner -------------------------------------------------------------

BaseField* FieldOwner::findField(std::string_view name) const {
  for (BaseField* field : m_fields)
    if (field->name() == name) return field;
  return nullptr;
}

std::vector<std::string> FieldOwner::fieldNames() const {
  std::vector<std::string> names;
  for (const BaseField* field : m_fields) names.push_back(field->name());
  return names;
}

// ---- BaseField --------------------------------------------------------------

BaseField::BaseField(FieldOwner* owner, std::string_view name, FieldInfo info)
    : m_owner(owner), m_name(name), m_info(info) {
  owner->m_fields.push_back(this);
}

std::optional<std::string> BaseField::assign(std::string_view text, const ParseContext& context,
                                             const SourceLocation& where) {
  if (auto error = parseAndStore(text, context)) return error;
  m_isSet = true;
  m_location = where;
  return std::nullopt;
}

const SourceLocation& BaseField::location() const { return m_isSet ? m_location : m_owner->location(); }

std::string BaseField::rangeText() const {
  if (!m_info.min && !m_info.max) return "";
  std::string s = m_info.min ? (m_info.minExclusive ? "(" : "[") + formatDouble(*m_info.min) : "(-inf";
  s += ", ";
  s += m_info.max ? formatDouble(*m_info.max) + "]" : "inf)";
  return s;
}

std::optional<std::string> BaseField::checkRange(double value) const {
  const bool belowMin = m_info.min && (m_info.minExclusive ? value <= *m_info.min : value < *m_info.min);
  const bool aboveMax = m_info.max && value > *m_info.max;
  if (belowMin || aboveMax) {
    return "value " + formatDouble(value) + " is out of range " + rangeText() +
           (m_info.unit.empty() ? "" : " " + std::string(m_info.unit));
  }
  return std::nullopt;
}

// ---- value parsing ----------------------------------------------------------

namespace {

std::optional<std::string> parseNumber(std::string_view text, double& out) {
  const std::string_view t = trim(text);
  if (t.empty()) return std::string("expected a number, got an empty value");
  const char* begin = t.data();
  // from_chars does not accept a leading '+'; one is allowed, but not "+-1".
  if (*begin == '+' && t.size() > 1 && t[1] != '-' && t[1] != '+') ++begin;
  const auto result = std::from_chars(begin, t.data() + t.size(), out);
  if (result.ec == std::errc::result_out_of_range)
    return "number '" + std::string(t) + "' is outside the range of a double (about 1e-308 to 1e308)";
  if (result.ec != std::errc() || result.ptr != t.data() + t.size())
    return "expected a number, got " + visiblyQuoted(t);
  if (!std::isfinite(out)) return "expected a finite number, got " + visiblyQuoted(t);
  return std::nullopt;
}

// Splits on whitespace and commas: "1 2 3" and "1, 2, 3" both read as three numbers.
std::vector<std::string_view> splitList(std::string_view text) {
  std::vector<std::string_view> parts;
  size_t i = 0;
  const auto isSeparator = [](char c) { return c == ',' || std::isspace(static_cast<unsigned char>(c)); };
  while (i < text.size()) {
    while (i < text.size() && isSeparator(text[i])) ++i;
    const size_t start = i;
    while (i < text.size() && !isSeparator(text[i])) ++i;
    if (i > start) parts.push_back(text.substr(start, i - start));
  }
  return parts;
}

}  // namespace

std::optional<std::string> FieldTraits<bool>::parse(std::string_view text, bool& out) {
  const std::string_view t = trim(text);
  if (t == "true" || t == "1") {
    out = true;
  } else if (t == "false" || t == "0") {
    out = false;
  } else {
    return "expected true or false, got " + visiblyQuoted(t);
  }
  return std::nullopt;
}
std::string FieldTraits<bool>::format(bool value) { return value ? "true" : "false"; }

std::optional<std::string> FieldTraits<int>::parse(std::string_view text, int& out) {
  const std::string_view t = trim(text);
  const char* begin = t.data();
  if (t.size() > 1 && *begin == '+' && t[1] != '-' && t[1] != '+') ++begin;
  const auto result = std::from_chars(begin, t.data() + t.size(), out);
  if (!t.empty() && result.ec == std::errc::result_out_of_range)
    return "integer '" + std::string(t) + "' is outside the range of an int";
  if (t.empty() || result.ec != std::errc() || result.ptr != t.data() + t.size())
    return "expected an integer, got " + visiblyQuoted(t);
  return std::nullopt;
}
std::string FieldTraits<int>::format(int value) { return std::to_string(value); }

std::optional<std::string> FieldTraits<double>::parse(std::string_view text, double& out) {
  return parseNumber(text, out);
}
std::string FieldTraits<double>::format(double value) { return formatDouble(value); }

std::optional<std::string> FieldTraits<std::string>::parse(std::string_view text, std::string& out) {
  out = std::string(text);
  return std::nullopt;
}

std::optional<std::string> FieldTraits<Vec3>::parse(std::string_view text, Vec3& out) {
  const auto parts = splitList(text);
  if (parts.size() != 3)
    return "expected three numbers 'x y z', got " + std::to_string(parts.size()) + " value(s) in '" +
           std::string(trim(text)) + "'";
  for (int i = 0; i < 3; ++i) {
    if (auto error = parseNumber(parts[i], out[i])) return error;
  }
  return std::nullopt;
}
std::string FieldTraits<Vec3>::format(const Vec3& v) {
  return formatDouble(v.x()) + " " + formatDouble(v.y()) + " " + formatDouble(v.z());
}

std::optional<std::string> FieldTraits<std::vector<double>>::parse(std::string_view text, std::vector<double>& out) {
  out.clear();
  for (std::string_view part : splitList(text)) {
    double v = 0;
    if (auto error = parseNumber(part, v)) return "in list: " + *error;
    out.push_back(v);
  }
  return std::nullopt;
}
std::string FieldTraits<std::vector<double>>::format(const std::vector<double>& value) {
  std::string s;
  for (size_t i = 0; i < value.size(); ++i) s += (i ? " " : "") + formatDouble(value[i]);
  return s;
}

// ---- RateField --------------------------------------------------------------

RateField::RateField(FieldOwner* owner, double defaultHz, std::string_view help)
    : Field<double>(owner, "rate", defaultHz,
                    // 1 mHz: one call in the longest run (RunPlan::kMaxDuration) is about the least that
                    // means anything; a rate below it is a unit slip (a period given for a rate).
                    {.help = help, .unit = "Hz", .min = 1.0e-3, .max = 1.0e6}),
      m_group(owner,
              "group",
              "",
              {.help = "Rate group: components of one rate and one group tick in one thread, in order; a name "
                       "of its own runs this component apart (a FEM beside the haptic loop at the same rate). "
                       "Empty: the rate's own group"}) {}

// ---- EnumField --------------------------------------------------------------

EnumField::EnumField(FieldOwner* owner, std::string_view name, std::vector<std::string> options,
                     std::string defaultValue, FieldInfo info)
    : BaseField(owner, name, info), m_options(std::move(options)) {
  const auto it = std::find(m_options.begin(), m_options.end(), defaultValue);
  m_defaultIndex = m_index = it == m_options.end() ? 0 : static_cast<size_t>(it - m_options.begin());
}

std::string EnumField::rangeText() const {
  std::string s = "one of: ";
  for (size_t i = 0; i < m_options.size(); ++i) s += (i ? ", " : "") + m_options[i];
  return s;
}

std::optional<std::string> EnumField::parseAndStore(std::string_view text, const ParseContext&) {
  const std::string_view t = trim(text);
  const auto it = std::find(m_options.begin(), m_options.end(), t);
  if (it == m_options.end())
    return "expected " + rangeText() + ", got " + visiblyQuoted(t) + didYouMean(t, m_options);
  m_index = static_cast<size_t>(it - m_options.begin());
  return std::nullopt;
}

// ---- FilePathField ----------------------------------------------------------

FilePathField::FilePathField(FieldOwner* owner, std::string_view name, FieldInfo info, Role role,
                             std::vector<std::string> schemes)
    : BaseField(owner, name, info), m_role(role), m_schemes(std::move(schemes)) {}

std::string_view FilePathField::schemeBody() const {
  return isScheme() ? std::string_view(m_text).substr(m_scheme.size() + 1) : std::string_view();
}

namespace {
std::string schemeList(const std::vector<std::string>& schemes) {
  std::string s;
  for (size_t i = 0; i < schemes.size(); ++i) s += (i ? ", " : "") + schemes[i] + ":...";
  return s;
}
}  // namespace

std::string FilePathField::rangeText() const {
  const std::string paths = m_role == Role::Input              ? "existing file"
                            : m_role == Role::InputOrDirectory ? "existing file or directory"
                                                               : "";
  if (m_schemes.empty()) return paths;
  return (paths.empty() ? "a path" : paths) + " or " + schemeList(m_schemes);
}

std::optional<std::string> FilePathField::parseAndStore(std::string_view text, const ParseContext& context) {
  const std::string t(trim(text));
  if (t.empty()) return std::string("expected a file path, got an empty value");
  // "name:rest" with a name of two or more letters is a scheme, not a path.
  const size_t colon = t.find(':');
  if (colon != std::string::npos && colon >= 2 &&
      std::all_of(t.begin(), t.begin() + static_cast<long>(colon),
                  [](char c) { return std::isalpha(static_cast<unsigned char>(c)); })) {
    const std::string scheme = t.substr(0, colon);
    if (std::find(m_schemes.begin(), m_schemes.end(), scheme) == m_schemes.end()) {
      return "unknown source '" + scheme + ":'" +
             (m_schemes.empty() ? std::string(", expected a file path")
                                : ", expected a file path or " + schemeList(m_schemes));
    }
    m_text = t;
    m_scheme = scheme;
    m_resolved.clear();
    return std::nullopt;
  }
  // A query after a directory ("DIR/?series=UID"): the path is before it.
  std::string pathText = t, query;
  if (m_role == Role::InputOrDirectory) {
    if (const size_t mark = t.find('?'); mark != std::string::npos) pathText = t.substr(0, mark), query = t.substr(mark);
  }
  std::filesystem::path p(pathText);
  if (p.is_relative()) p = context.baseDirectory / p;
  p = p.lexically_normal();
  std::error_code ec;
  if (m_role == Role::Input) {
    if (!std::filesystem::exists(p, ec)) return "file not found: " + p.string();
    if (!std::filesystem::is_regular_file(p, ec)) return "not a regular file: " + p.string();
  } else if (m_role == Role::InputOrDirectory) {
    if (!std::filesystem::exists(p, ec)) return "file or directory not found: " + p.string();
    const bool directory = std::filesystem::is_directory(p, ec);
    if (!directory && !std::filesystem::is_regular_file(p, ec)) return "not a regular file or directory: " + p.string();
    if (!query.empty() && !directory)
      return "'" + query + "' follows a file: a query picks within a directory (a DICOM series), e.g. DIR/?series=UID";
  }
  if (!query.empty()) {
    // lexically_normal() keeps a trailing slash as an empty last part; the
    // reader wants the directory.
    if (p.filename().empty()) p = p.parent_path();
    p += query;
  }
  m_text = t;
  m_scheme.clear();
  m_resolved = p;
  return std::nullopt;
}

}  // namespace trephine

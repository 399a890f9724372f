#pragma once
// Minimal streaming JSON writer with stable formatting (two-space indent,
// shortest round-trip numbers, non-finite numbers written as null).
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace trephine {

class JsonWriter {
 public:
  explicit JsonWriter(std::ostream& out) : m_out(out) {}

  JsonWriter& beginObject();
  JsonWriter& endObject();
  JsonWriter& beginArray();
  JsonWriter& endArray();
  JsonWriter& key(std::string_view name);
  JsonWriter& value(std::string_view text);
  JsonWriter& value(const char* text) { return value(std::string_view(text)); }
  JsonWriter& value(const std::string& text) { return value(std::string_view(text)); }
  JsonWriter& value(double number);
  JsonWriter& value(int number) { return value(static_cast<long long>(number)); }
  JsonWriter& value(long long number);
  JsonWriter& value(unsigned long long number);
  JsonWriter& value(unsigned long number) { return value(static_cast<unsigned long long>(number)); }
  JsonWriter& value(long number) { return value(static_cast<long long>(number)); }
  JsonWriter& value(unsigned number) { return value(static_cast<unsigned long long>(number)); }
  JsonWriter& value(bool flag);
  JsonWriter& null();

  template <class T>
  JsonWriter& field(std::string_view name, const T& v) {
    key(name);
    return value(v);
  }

  static std::string escape(std::string_view text);

 private:
  void beforeValue();
  void newline();
  std::ostream& m_out;
  struct Level {
    bool isObject;
    bool empty;
  };
  std::vector<Level> m_stack;
  bool m_afterKey = false;
};

}  // namespace trephine

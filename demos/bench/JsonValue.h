// A small JSON value tree and writer for the benchmark's summary (no dependency).
// Objects keep their keys in insertion order so the summary reads top to bottom.
#pragma once

#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace btbench {

class JsonValue {
public:
    enum class Kind { Null, Bool, Number, String, Array, Object };

    JsonValue() = default;  // null
    JsonValue(bool b) : m_kind(Kind::Bool), m_bool(b) {}
    JsonValue(int n) : m_kind(Kind::Number), m_number(n) {}
    JsonValue(long n) : m_kind(Kind::Number), m_number(double(n)) {}
    JsonValue(long long n) : m_kind(Kind::Number), m_number(double(n)) {}
    JsonValue(double n) : m_kind(Kind::Number), m_number(n) {}
    JsonValue(const char* s) : m_kind(Kind::String), m_string(s) {}
    JsonValue(std::string s) : m_kind(Kind::String), m_string(std::move(s)) {}

    static JsonValue object() { JsonValue v; v.m_kind = Kind::Object; return v; }
    static JsonValue array() { JsonValue v; v.m_kind = Kind::Array; return v; }

    // Object access: adds the key (at the end) when it is new.
    JsonValue& operator[](const std::string& key);
    // Array append.
    void push(JsonValue v);

    Kind kind() const { return m_kind; }
    // Writes indented JSON; non-finite numbers become null (JSON has no NaN).
    void write(std::ostream& out, int indent = 0) const;

private:
    Kind m_kind = Kind::Null;
    bool m_bool = false;
    double m_number = 0;
    std::string m_string;
    std::vector<JsonValue> m_items;
    std::vector<std::pair<std::string, JsonValue>> m_members;
};

std::string jsonEscape(const std::string& s);

}  // namespace btbench

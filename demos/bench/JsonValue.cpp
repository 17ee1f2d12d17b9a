#include "JsonValue.h"

#include <cmath>
#include <cstdio>

namespace btbench {

JsonValue& JsonValue::operator[](const std::string& key) {
    if (m_kind == Kind::Null) m_kind = Kind::Object;
    for (auto& member : m_members)
        if (member.first == key) return member.second;
    m_members.emplace_back(key, JsonValue());
    return m_members.back().second;
}

void JsonValue::push(JsonValue v) {
    if (m_kind == Kind::Null) m_kind = Kind::Array;
    m_items.push_back(std::move(v));
}

std::string jsonEscape(const std::string& s) {
    std::string out;
    for (unsigned char c : s) {
        switch (c) {
        case '"': out += "\\\""; break;
        case '\\': out += "\\\\"; break;
        case '\n': out += "\\n"; break;
        case '\t': out += "\\t"; break;
        case '\r': out += "\\r"; break;
        default:
            if (c < 0x20) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\u%04x", c);
                out += buf;
            } else {
                out += char(c);
            }
        }
    }
    return out;
}

static void writeNumber(std::ostream& out, double n) {
    if (!std::isfinite(n)) { out << "null"; return; }
    if (n == std::floor(n) && std::fabs(n) < 1e15) { out << (long long)n; return; }
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", n);
    out << buf;
}

void JsonValue::write(std::ostream& out, int indent) const {
    const std::string pad(size_t(indent + 2), ' '), closePad(size_t(indent), ' ');
    switch (m_kind) {
    case Kind::Null: out << "null"; break;
    case Kind::Bool: out << (m_bool ? "true" : "false"); break;
    case Kind::Number: writeNumber(out, m_number); break;
    case Kind::String: out << '"' << jsonEscape(m_string) << '"'; break;
    case Kind::Array: {
        // Arrays of plain values stay on one line; they are short (e.g. per-phase lists).
        bool flat = true;
        for (auto& item : m_items) flat = flat && item.m_kind != Kind::Object && item.m_kind != Kind::Array;
        out << '[';
        for (size_t i = 0; i < m_items.size(); ++i) {
            if (i) out << (flat ? ", " : ",");
            if (!flat) out << '\n' << pad;
            m_items[i].write(out, indent + 2);
        }
        if (!flat && !m_items.empty()) out << '\n' << closePad;
        out << ']';
        break;
    }
    case Kind::Object:
        out << '{';
        for (size_t i = 0; i < m_members.size(); ++i) {
            out << (i ? ",\n" : "\n") << pad << '"' << jsonEscape(m_members[i].first) << "\": ";
            m_members[i].second.write(out, indent + 2);
        }
        if (!m_members.empty()) out << '\n' << closePad;
        out << '}';
        break;
    }
}

}  // namespace btbench

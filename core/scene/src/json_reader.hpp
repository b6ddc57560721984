// Private helper: typed reads from a JSON object with JSON-pointer error locations, and a check
// that no unknown key is left over. Used only by the scene parser.
#pragma once

#include "names.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/types.hpp"

#include <cmath>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

namespace polycut::scene::detail {

using nlohmann::json;

inline std::string escape_pointer_token(const std::string& key) {
    std::string out;
    for (char c : key) {
        if (c == '~')
            out += "~0";
        else if (c == '/')
            out += "~1";
        else
            out += c;
    }
    return out;
}

/// A JSON object being read; every key read is remembered so finish() can reject the rest.
class ObjectReader {
public:
    ObjectReader(const json& j, std::string pointer)
        : m_json(j)
        , m_pointer(std::move(pointer)) {
        if (!j.is_object())
            fail("", "must be an object");
    }

    const std::string& pointer() const { return m_pointer; }
    std::string child(const std::string& key) const {
        return m_pointer + "/" + escape_pointer_token(key);
    }

    [[noreturn]] void fail(const std::string& key, const std::string& what) const {
        throw SceneError(key.empty() ? (m_pointer.empty() ? "/" : m_pointer) : child(key), what);
    }

    bool has(const std::string& key) {
        m_seen.insert(key);
        return m_json.contains(key);
    }
    const json& get(const std::string& key) {
        if (!has(key))
            fail(key, "is required");
        return m_json.at(key);
    }

    double number(const std::string& key, double fallback, double lo, double hi,
        bool lo_open = false, const char* unit = "") {
        if (!has(key))
            return fallback;
        return number_required(key, lo, hi, lo_open, unit);
    }
    double number_required(
        const std::string& key, double lo, double hi, bool lo_open = false, const char* unit = "") {
        const json& v = get(key);
        if (!v.is_number())
            fail(key, "must be a number" + unit_suffix(unit));
        const double x = v.get<double>();
        const bool below = lo_open ? !(x > lo) : !(x >= lo);
        if (!std::isfinite(x) || below || !(x <= hi))
            fail(key,
                "must be in " + std::string(lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + "]"
                    + unit_suffix(unit) + ", got " + fmt(x));
        return x;
    }
    long integer(const std::string& key, long fallback, long lo, long hi) {
        if (!has(key))
            return fallback;
        const json& v = get(key);
        if (!v.is_number_integer())
            fail(key, "must be an integer");
        const long x = v.get<long>();
        if (x < lo || x > hi)
            fail(key,
                "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi)
                    + "], got " + std::to_string(x));
        return x;
    }
    bool boolean(const std::string& key, bool fallback) {
        if (!has(key))
            return fallback;
        const json& v = get(key);
        if (!v.is_boolean())
            fail(key, "must be true or false");
        return v.get<bool>();
    }
    std::string string(const std::string& key, const std::string& fallback) {
        if (!has(key))
            return fallback;
        const json& v = get(key);
        if (!v.is_string())
            fail(key, "must be a string");
        return v.get<std::string>();
    }
    /// An enum option read by its name in `table` (names.hpp); an unknown name fails with the
    /// accepted names. Absent: `fallback`.
    template <class E, std::size_t N>
    E choice(const std::string& key, E fallback, const Name<E> (&table)[N]) {
        if (!has(key))
            return fallback;
        const std::string s = string(key, "");
        for (const auto& n : table)
            if (s == n.text)
                return n.value;
        std::string list;
        for (const auto& n : table)
            list += (list.empty() ? "\"" : ", \"") + std::string(n.text) + "\"";
        fail(key, "must be one of " + list + ", got \"" + s + "\"");
    }
    /// The same, required.
    template <class E, std::size_t N>
    E choice_required(const std::string& key, const Name<E> (&table)[N]) {
        get(key);
        return choice(key, table[0].value, table);
    }
    Vec3 vec3(const std::string& key, const Vec3& fallback, bool required = false,
        const char* unit = "") {
        if (!has(key)) {
            if (required)
                fail(key, "is required");
            return fallback;
        }
        return parse_vec3(get(key), child(key), unit);
    }

    /// Rejects keys that were never read.
    void finish() const {
        for (auto it = m_json.begin(); it != m_json.end(); ++it)
            if (!m_seen.count(it.key()))
                fail(it.key(), "unknown key (allowed: " + allowed_list() + ")");
    }

    static Vec3 parse_vec3(const json& v, const std::string& ptr, const char* unit = "") {
        if (!v.is_array() || v.size() != 3)
            throw SceneError(ptr, "must be an array of 3 numbers" + unit_suffix(unit));
        Vec3 out;
        for (int i = 0; i < 3; ++i) {
            const json& e = v[std::size_t(i)];
            if (!e.is_number() || !std::isfinite(e.get<double>()))
                throw SceneError(ptr + "/" + std::to_string(i), "must be a finite number");
            out[i] = e.get<double>();
        }
        return out;
    }

private:
    static std::string unit_suffix(const char* unit) {
        return unit && *unit ? std::string(" [") + unit + "]" : std::string();
    }
    static std::string fmt(double x) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", x);
        return buf;
    }
    std::string allowed_list() const {
        std::string s;
        for (const auto& k : m_seen)
            s += (s.empty() ? "" : ", ") + k;
        return s;
    }

    const json& m_json;
    std::string m_pointer;
    std::set<std::string> m_seen;
};

} // namespace polycut::scene::detail

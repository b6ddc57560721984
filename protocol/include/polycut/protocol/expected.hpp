// A value or an error, for wire-facing functions that never throw (STYLE.md "Bad input").
// C++20 has no std::expected; this is the small subset the protocol needs.
#pragma once

#include <utility>
#include <variant>

namespace polycut::protocol {

/// Either a `T` (success) or an `E` (failure). Accessing the wrong side is a programming error
/// (std::bad_variant_access), so check `ok()` first.
template <class T, class E> class Expected {
public:
    /// Success.
    Expected(T value)
        : m_data(std::in_place_index<0>, std::move(value)) { }
    /// Failure.
    Expected(E error)
        : m_data(std::in_place_index<1>, std::move(error)) { }

    /// True when a value is held.
    bool ok() const { return m_data.index() == 0; }
    /// Same as ok().
    explicit operator bool() const { return ok(); }

    /// The value (requires ok()).
    T& value() & { return std::get<0>(m_data); }
    const T& value() const& { return std::get<0>(m_data); }
    T&& value() && { return std::get<0>(std::move(m_data)); }
    /// Member access to the value (requires ok()).
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }

    /// The error (requires !ok()).
    E& error() & { return std::get<1>(m_data); }
    const E& error() const& { return std::get<1>(m_data); }

private:
    std::variant<T, E> m_data;
};

} // namespace polycut::protocol

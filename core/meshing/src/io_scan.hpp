// Private to the meshing module: structural scans of surface files before CGAL parses them.
//
// CGAL 5.5's readers size their buffers from counts the file declares (OFF vertex and face
// counts, per-face vertex counts, PLY list lengths), report failures without a position, and
// in a few cases misread or crash (PLY integer coordinates, binary OFF face colour counts). The
// scans below walk each file once, check every count against the bytes that are left, every
// number for finiteness and every index for range, and throw FileError with the line (text)
// or byte offset (binary) and the problem. CGAL then parses a file that is known to be sound,
// and the caller cross-checks CGAL's result against the scan's counts. Binary OFF is read here
// directly (scan_off() returns its soup).
#pragma once

#include "polycut/common/error.hpp"
#include "polycut/common/types.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace polycut::meshing::detail {

/// Surface file formats.
enum class SurfaceFormat { Off, Obj, Stl, Ply };

/// What a scan found: counts to cross-check CGAL's result against, and where each polygon
/// starts (for messages about a polygon).
struct SurfaceScan {
    bool binary = false; ///< positions below are byte offsets, else line numbers
    long vertices = -1; ///< vertex count (-1 for STL: CGAL merges repeated corners)
    long polygons = 0; ///< polygon count
    long corners = 0; ///< sum of the polygons' vertex counts
    std::vector<long> polygon_at; ///< line or byte offset of each polygon
    /// Binary OFF only: the soup itself (CGAL's soup reader does not skip the per-face colour
    /// count of binary OFF, so it is read here).
    std::vector<Vec3> points;
    std::vector<std::vector<std::size_t>> soup;
    bool has_soup = false;
};

/// Largest surface file read [bytes]: a bound on memory, far above any organ surface.
inline constexpr std::size_t kMaxSurfaceFileBytes = std::size_t(1) << 30;
/// Largest polygon accepted [vertices].
inline constexpr long kMaxPolygonVertices = 1 << 16;

/// Per-format scans of the whole file `bytes` read from `path`. Each throws FileError.
SurfaceScan scan_off(const std::string& path, std::string_view bytes);
SurfaceScan scan_obj(const std::string& path, std::string_view bytes);
SurfaceScan scan_stl(const std::string& path, std::string_view bytes);
SurfaceScan scan_ply(const std::string& path, std::string_view bytes);

/// Iterates the lines of a text and the whitespace-separated tokens in them, counting lines
/// from 1.
class TextCursor {
public:
    explicit TextCursor(std::string_view text)
        : m_text(text) { }

    /// The next line without its end-of-line characters; false at the end of the text.
    bool next_line(std::string_view& line) {
        if (m_pos >= m_text.size())
            return false;
        const std::size_t end = m_text.find('\n', m_pos);
        const std::size_t stop = end == std::string_view::npos ? m_text.size() : end;
        line = m_text.substr(m_pos, stop - m_pos);
        if (!line.empty() && line.back() == '\r')
            line.remove_suffix(1);
        m_pos = stop + 1;
        ++m_line;
        return true;
    }

    /// The next token of the text, across lines; false at the end.
    bool next_token(std::string_view& token) {
        while (m_pos < m_text.size() && is_space(m_text[m_pos])) {
            if (m_text[m_pos] == '\n')
                ++m_line;
            ++m_pos;
        }
        if (m_pos >= m_text.size())
            return false;
        const std::size_t start = m_pos;
        while (m_pos < m_text.size() && !is_space(m_text[m_pos]))
            ++m_pos;
        token = m_text.substr(start, m_pos - start);
        token_line = m_line + 1;
        return true;
    }

    /// Line of the last line returned by next_line() (1-based).
    long line() const { return m_line; }
    /// Line of the last token returned by next_token() (1-based).
    long token_line = 0;
    /// Offset of the first character not consumed yet.
    std::size_t position() const { return m_pos; }
    /// Bytes not consumed yet.
    std::size_t remaining() const { return m_pos < m_text.size() ? m_text.size() - m_pos : 0; }

    static bool is_space(char c) {
        return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
    }

private:
    std::string_view m_text;
    std::size_t m_pos = 0;
    long m_line = 0; ///< newlines consumed (next_token) or lines returned (next_line)
};

/// Splits a line into whitespace-separated tokens.
inline std::vector<std::string_view> split_tokens(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && TextCursor::is_space(line[i]))
            ++i;
        const std::size_t start = i;
        while (i < line.size() && !TextCursor::is_space(line[i]))
            ++i;
        if (i > start)
            out.push_back(line.substr(start, i - start));
    }
    return out;
}

/// Parses a whole token as a finite double (a leading '+' allowed); false otherwise.
inline bool parse_finite(std::string_view token, double& value) {
    if (!token.empty() && token.front() == '+')
        token.remove_prefix(1);
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return ec == std::errc() && end == token.data() + token.size() && std::isfinite(value);
}

/// Parses a whole token as an integer; false otherwise.
inline bool parse_integer(std::string_view token, long long& value) {
    if (!token.empty() && token.front() == '+')
        token.remove_prefix(1);
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return ec == std::errc() && end == token.data() + token.size();
}

/// "'<token>'" shortened to 24 characters, non-printable bytes as '?', for messages.
inline std::string quote(std::string_view token) {
    std::string s = "'";
    for (std::size_t i = 0; i < token.size() && i < 24; ++i)
        s += (token[i] >= 32 && token[i] < 127) ? token[i] : '?';
    return s + (token.size() > 24 ? "...'" : "'");
}

/// Reads fixed-size numbers from a byte buffer with bounds checks.
class ByteCursor {
public:
    ByteCursor(std::string_view bytes, std::size_t start, bool big_endian)
        : m_bytes(bytes)
        , m_pos(start)
        , m_big(big_endian) { }

    std::size_t position() const { return m_pos; }
    std::size_t remaining() const { return m_pos < m_bytes.size() ? m_bytes.size() - m_pos : 0; }

    /// Reads a T (integer or floating point, sizeof 1..8) in the cursor's byte order; false if
    /// fewer than sizeof(T) bytes are left.
    template <class T> bool read(T& value) {
        if (remaining() < sizeof(T))
            return false;
        unsigned char buf[sizeof(T)];
        std::memcpy(buf, m_bytes.data() + m_pos, sizeof(T));
        if (m_big != (std::endian::native == std::endian::big))
            for (std::size_t i = 0; i < sizeof(T) / 2; ++i)
                std::swap(buf[i], buf[sizeof(T) - 1 - i]);
        std::memcpy(&value, buf, sizeof(T));
        m_pos += sizeof(T);
        return true;
    }

    bool skip(std::size_t n) {
        if (remaining() < n)
            return false;
        m_pos += n;
        return true;
    }

private:
    std::string_view m_bytes;
    std::size_t m_pos;
    bool m_big;
};

/// FileError at a byte offset (line 0; the offset leads the problem).
inline FileError byte_error(const std::string& path, std::size_t offset, const std::string& what) {
    return FileError(path, 0, "byte " + std::to_string(offset) + ": " + what);
}

} // namespace polycut::meshing::detail

// Line reader and strict number parsing for the mesh file readers.
#include "io_text.hpp"

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

namespace polycut::mesh::io {

std::string quoted(std::string_view token) {
    if (token.size() > 40)
        return "'" + std::string(token.substr(0, 37)) + "...'";
    return "'" + std::string(token) + "'";
}

LineReader::LineReader(std::string path, char comment)
    : m_path(std::move(path))
    , m_comment(comment) {
    std::ifstream in(m_path, std::ios::binary);
    if (!in)
        throw FileError(m_path, 0, std::string("cannot open file: ") + std::strerror(errno));
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad())
        throw FileError(m_path, 0, "read error");
    m_content = std::move(buffer).str();
}

bool LineReader::next() {
    while (m_pos < m_content.size()) {
        std::size_t end = m_content.find('\n', m_pos);
        if (end == std::string::npos)
            end = m_content.size();
        std::string_view line(m_content.data() + m_pos, end - m_pos);
        m_pos = end + 1;
        ++m_line;
        if (m_comment != '\0')
            line = line.substr(0, line.find(m_comment));
        m_tokens.clear();
        std::size_t i = 0;
        while (i < line.size()) {
            while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i])))
                ++i;
            const std::size_t start = i;
            while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i])))
                ++i;
            if (i > start)
                m_tokens.push_back(line.substr(start, i - start));
        }
        if (m_tokens.empty())
            continue;
        m_text = std::string_view(m_tokens.front().data(),
            std::size_t(m_tokens.back().data() + m_tokens.back().size() - m_tokens.front().data()));
        return true;
    }
    m_tokens.clear();
    m_text = {};
    return false;
}

void LineReader::next_or_fail(const std::string& context) {
    if (!next())
        fail("unexpected end of file " + context);
}

void LineReader::fail(const std::string& problem) const {
    throw FileError(m_path, m_line, problem);
}

void LineReader::expect_tokens(std::size_t n, const std::string& what, bool at_least) const {
    if (m_tokens.size() == n || (at_least && m_tokens.size() > n))
        return;
    fail(what + ": expected " + (at_least ? "at least " : "") + std::to_string(n) + " value"
        + (n == 1 ? "" : "s") + ", found " + std::to_string(m_tokens.size()));
}

double LineReader::real(std::size_t i, const std::string& what) const {
    if (i >= m_tokens.size())
        fail(what + " missing");
    std::string_view t = m_tokens[i];
    if (!t.empty() && t.front() == '+')
        t.remove_prefix(1);
    double v = 0;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec == std::errc::result_out_of_range)
        fail(what + " " + quoted(m_tokens[i]) + " is out of the range of a double");
    if (ec != std::errc() || ptr != t.data() + t.size())
        fail(what + " " + quoted(m_tokens[i]) + " is not a number");
    if (!std::isfinite(v))
        fail(what + " " + quoted(m_tokens[i]) + " is not finite");
    return v;
}

long LineReader::integer(std::size_t i, const std::string& what, long lo, long hi) const {
    if (i >= m_tokens.size())
        fail(what + " missing");
    std::string_view t = m_tokens[i];
    if (!t.empty() && t.front() == '+')
        t.remove_prefix(1);
    long v = 0;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (ec == std::errc::result_out_of_range)
        fail(what + " " + quoted(m_tokens[i]) + " is out of range");
    if (ec != std::errc() || ptr != t.data() + t.size())
        fail(what + " " + quoted(m_tokens[i]) + " is not an integer");
    if (v < lo || v > hi)
        fail(what + " " + std::to_string(v) + " is out of range [" + std::to_string(lo) + ", "
            + std::to_string(hi) + "]");
    return v;
}

} // namespace polycut::mesh::io

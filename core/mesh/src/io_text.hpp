// Private helpers of the mesh file readers: a line reader that splits lines into tokens, parses
// numbers strictly, and throws FileError(path, line, problem) for anything unexpected.
#pragma once

#include "polycut/common/error.hpp"
#include "polycut/common/types.hpp"

#include <limits>
#include <string>
#include <string_view>
#include <vector>

namespace polycut::mesh::io {

/// Reads a text file line by line. Lines that are empty (after dropping a comment, when a
/// comment character is given, and a trailing '\r') are skipped.
class LineReader {
public:
    /// Opens `path`; throws FileError(path, 0, ...) when it cannot be read.
    explicit LineReader(std::string path, char comment = '\0');

    /// Advances to the next non-empty line; false at the end of the file.
    bool next();
    /// Advances to the next non-empty line; throws "unexpected end of file" + `context` at the end.
    void next_or_fail(const std::string& context);

    const std::string& path() const { return m_path; }
    long line() const { return m_line; }
    /// The current line (comment and surrounding blanks removed).
    std::string_view text() const { return m_text; }
    const std::vector<std::string_view>& tokens() const { return m_tokens; }
    std::size_t size() const { return m_tokens.size(); }

    /// Throws FileError at the current line.
    [[noreturn]] void fail(const std::string& problem) const;
    /// Throws unless the current line has exactly `n` tokens (or at least `n` when `at_least`).
    void expect_tokens(std::size_t n, const std::string& what, bool at_least = false) const;
    /// Token i as a finite double; `what` names the value in the error.
    double real(std::size_t i, const std::string& what) const;
    /// Token i as an integer in [lo, hi].
    long integer(std::size_t i, const std::string& what, long lo = std::numeric_limits<long>::min(),
        long hi = std::numeric_limits<long>::max()) const;

private:
    std::string m_path;
    char m_comment;
    std::string m_content;
    std::size_t m_pos = 0;
    long m_line = 0;
    std::string_view m_text;
    std::vector<std::string_view> m_tokens;
};

/// Quotes a token for an error message, shortened when long.
std::string quoted(std::string_view token);

} // namespace polycut::mesh::io

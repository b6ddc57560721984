// OFF files: the structural scan of ASCII OFF (the layout CGAL's File_scanner_OFF reads: a
// header keyword, the counts, one vertex per line, one face per line, '#' comments) and the
// reader of binary OFF (Geomview: "OFF BINARY", big-endian int32 counts, float32 coordinates,
// faces as int32 n, n int32 ids, int32 colour count and that many float32).
#include "io_scan.hpp"

#include <algorithm>

namespace polycut::meshing::detail {

namespace {

/// The line without a '#' comment.
std::string_view strip_comment(std::string_view line) {
    const std::size_t hash = line.find('#');
    return hash == std::string_view::npos ? line : line.substr(0, hash);
}

/// Next token, skipping '#' comments to the end of their line.
bool next_data_token(TextCursor& text, std::string_view& token) {
    while (text.next_token(token)) {
        if (token.front() != '#')
            return true;
        std::string_view rest;
        text.next_line(rest);
    }
    return false;
}

/// Next line with data (not blank, not a comment), with its comment stripped.
bool next_data_line(TextCursor& text, std::vector<std::string_view>& tokens) {
    std::string_view line;
    while (text.next_line(line)) {
        tokens = split_tokens(strip_comment(line));
        if (!tokens.empty())
            return true;
    }
    return false;
}

/// Reads one header count; `what` names it ("vertex count"), `items` what it counts.
long read_count(const std::string& path, TextCursor& text, const char* what, const char* items,
    std::size_t min_bytes_each) {
    std::string_view token;
    if (!next_data_token(text, token))
        throw FileError(path, text.token_line, std::string("file ends before the ") + what);
    long long n = 0;
    if (!parse_integer(token, n) || n < 0)
        throw FileError(path, text.token_line,
            std::string("the ") + what + " is " + quote(token) + ", not a non-negative integer");
    if (min_bytes_each > 0 && std::size_t(n) > text.remaining() / min_bytes_each + 1)
        throw FileError(path, text.token_line,
            std::string("the header declares ") + std::to_string(n) + " " + items + " but only "
                + std::to_string(text.remaining()) + " bytes follow");
    return long(n);
}

SurfaceScan scan_off_binary(const std::string& path, std::string_view bytes, std::size_t start) {
    SurfaceScan scan;
    scan.binary = true;
    scan.has_soup = true;
    ByteCursor in(bytes, start, true);
    std::int32_t nv = 0, nf = 0, ne = 0;
    if (!in.read(nv) || !in.read(nf) || !in.read(ne))
        throw byte_error(path, in.position(), "file ends inside the binary OFF counts");
    if (nv < 0 || nf <= 0)
        throw byte_error(path, start,
            "binary OFF declares " + std::to_string(nv) + " vertices and " + std::to_string(nf)
                + " faces");
    // 12 bytes per vertex, at least 20 per face (count, three ids, colour count).
    if (std::size_t(nv) * 12 + std::size_t(nf) * 20 > in.remaining())
        throw byte_error(path, start,
            "binary OFF declares " + std::to_string(nv) + " vertices and " + std::to_string(nf)
                + " faces, more than the " + std::to_string(in.remaining())
                + " bytes that follow can hold");
    scan.vertices = nv;
    scan.points.reserve(std::size_t(nv));
    for (std::int32_t v = 0; v < nv; ++v) {
        const std::size_t at = in.position();
        float x = 0, y = 0, z = 0;
        if (!in.read(x) || !in.read(y) || !in.read(z))
            throw byte_error(path, at, "file ends inside vertex " + std::to_string(v));
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
            throw byte_error(path, at, "vertex " + std::to_string(v) + " is not finite");
        scan.points.emplace_back(x, y, z);
    }
    scan.soup.reserve(std::size_t(nf));
    for (std::int32_t f = 0; f < nf; ++f) {
        const std::size_t at = in.position();
        std::int32_t n = 0;
        if (!in.read(n))
            throw byte_error(path, at, "file ends before face " + std::to_string(f));
        if (n < 3 || n > kMaxPolygonVertices || std::size_t(n) * 4 + 4 > in.remaining())
            throw byte_error(path, at,
                "face " + std::to_string(f) + " declares " + std::to_string(n) + " vertices (3 to "
                    + std::to_string(kMaxPolygonVertices) + ", within the file)");
        std::vector<std::size_t> polygon(static_cast<std::size_t>(n));
        for (std::size_t k = 0; k < polygon.size(); ++k) {
            std::int32_t id = 0;
            in.read(id);
            if (id < 0 || id >= nv)
                throw byte_error(path, at,
                    "face " + std::to_string(f) + " uses vertex " + std::to_string(id)
                        + ", out of range [0, " + std::to_string(nv) + ")");
            polygon[k] = std::size_t(id);
        }
        std::int32_t colours = 0;
        if (!in.read(colours) || colours < 0 || colours > 4 || !in.skip(std::size_t(colours) * 4))
            throw byte_error(path, at,
                "face " + std::to_string(f)
                    + " has no valid colour count (an int32 in [0, 4] and that many floats)");
        scan.polygon_at.push_back(long(at));
        scan.corners += n;
        scan.soup.push_back(std::move(polygon));
    }
    scan.polygons = nf;
    return scan;
}

} // namespace

SurfaceScan scan_off(const std::string& path, std::string_view bytes) {
    TextCursor text(bytes);
    std::string_view keyword;
    if (!next_data_token(text, keyword))
        throw FileError(path, 1, "no OFF header");
    // [C][N]OFF: colours and normals are extra numbers on the vertex lines. Homogeneous (4OFF),
    // n-dimensional (nOFF) and textured (STOFF) variants are not surfaces we mesh.
    if (keyword != "OFF" && keyword != "COFF" && keyword != "NOFF" && keyword != "CNOFF")
        throw FileError(path, text.token_line,
            "header " + quote(keyword) + " is not OFF (OFF, COFF, NOFF or CNOFF)");
    {
        // "OFF BINARY": the binary data starts after that line.
        TextCursor peek = text;
        std::string_view next;
        if (peek.next_token(next) && next == "BINARY") {
            if (keyword != "OFF")
                throw FileError(path, peek.token_line,
                    "binary " + std::string(keyword) + " is not supported (only OFF BINARY)");
            std::string_view rest;
            peek.next_line(rest);
            return scan_off_binary(path, bytes, peek.position());
        }
    }
    SurfaceScan scan;
    // An ASCII vertex needs >= 6 bytes ("0 0 0\n"), a face >= 8 ("3 0 1 2\n").
    const long nv = read_count(path, text, "vertex count", "vertices", 6);
    const long nf = read_count(path, text, "face count", "faces", 8);
    read_count(path, text, "edge count", "edges", 0);
    {
        std::string_view rest;
        text.next_line(rest);
        if (!split_tokens(strip_comment(rest)).empty())
            throw FileError(path, text.line(), "unexpected data after the three counts");
    }
    if (nf == 0)
        throw FileError(path, text.line(), "the header declares no faces");
    scan.vertices = nv;
    std::vector<std::string_view> tokens;
    for (long v = 0; v < nv; ++v) {
        if (!next_data_line(text, tokens))
            throw FileError(path, text.line(),
                "file ends after " + std::to_string(v) + " of " + std::to_string(nv) + " vertices");
        double x = 0;
        for (std::size_t k = 0; k < 3; ++k)
            if (k >= tokens.size() || !parse_finite(tokens[k], x))
                throw FileError(path, text.line(),
                    "vertex " + std::to_string(v) + ": "
                        + (k >= tokens.size()
                                ? "fewer than 3 coordinates"
                                : "coordinate " + quote(tokens[k]) + " is not a finite number"));
    }
    scan.polygon_at.reserve(std::size_t(std::min<long>(nf, long(text.remaining() / 8 + 1))));
    for (long f = 0; f < nf; ++f) {
        if (!next_data_line(text, tokens))
            throw FileError(path, text.line(),
                "file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
        long long n = 0;
        if (!parse_integer(tokens[0], n) || n < 3 || n > kMaxPolygonVertices)
            throw FileError(path, text.line(),
                "face " + std::to_string(f) + ": vertex count " + quote(tokens[0])
                    + " is not an integer in [3, " + std::to_string(kMaxPolygonVertices) + "]");
        if (std::size_t(n) + 1 > tokens.size())
            throw FileError(path, text.line(),
                "face " + std::to_string(f) + " declares " + std::to_string(n)
                    + " vertices but lists " + std::to_string(tokens.size() - 1));
        for (std::size_t k = 1; k <= std::size_t(n); ++k) {
            long long id = 0;
            if (!parse_integer(tokens[k], id) || id < 0 || id >= nv)
                throw FileError(path, text.line(),
                    "face " + std::to_string(f) + ": vertex id " + quote(tokens[k])
                        + " is not an integer in [0, " + std::to_string(nv) + ")");
        }
        scan.polygon_at.push_back(text.line());
        scan.corners += long(n);
    }
    scan.polygons = nf;
    return scan;
}

} // namespace polycut::meshing::detail

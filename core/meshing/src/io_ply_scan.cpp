// The structural scan of PLY files (ASCII and binary, either byte order): the header, checked
// for what CGAL's PLY reader needs (float or double x, y, z on "vertex"; an int or uint list
// "vertex_indices" or "vertex_index" on "face"; integer list counts; known types), then every
// element walked with its list lengths bounded by the bytes left.
#include "io_scan.hpp"

#include <array>
#include <limits>

namespace polycut::meshing::detail {

namespace {

struct PlyType {
    std::string_view name, alias;
    int size; ///< bytes
    bool floating;
    bool is_signed;
};

constexpr std::array<PlyType, 8> kTypes { {
    { "char", "int8", 1, false, true },
    { "uchar", "uint8", 1, false, false },
    { "short", "int16", 2, false, true },
    { "ushort", "uint16", 2, false, false },
    { "int", "int32", 4, false, true },
    { "uint", "uint32", 4, false, false },
    { "float", "float32", 4, true, true },
    { "double", "float64", 8, true, true },
} };

const PlyType* find_type(std::string_view name) {
    for (const PlyType& t : kTypes)
        if (t.name == name || t.alias == name)
            return &t;
    return nullptr;
}

enum class Role { Other, Coordinate, Indices };

struct PlyProperty {
    std::string name;
    const PlyType* type = nullptr; ///< scalar type, or list item type
    const PlyType* count_type = nullptr; ///< list count type; nullptr for a scalar
    Role role = Role::Other;
};

struct PlyElement {
    std::string name;
    long long count = 0;
    long line = 0;
    std::vector<PlyProperty> properties;
    bool is_vertex() const { return name == "vertex" || name == "vertices"; }
    bool is_face() const { return name == "face" || name == "faces"; }
};

/// Reads one number of `type` (binary) as a double and, for integers, as an integer.
bool read_binary(ByteCursor& in, const PlyType& type, double& value, long long& integer) {
    auto get = [&](auto t) {
        if (!in.read(t))
            return false;
        value = double(t);
        integer = std::is_integral_v<decltype(t)> ? (long long)(t) : 0;
        return true;
    };
    switch (type.size) {
    case 1:
        return type.is_signed ? get(std::int8_t()) : get(std::uint8_t());
    case 2:
        return type.is_signed ? get(std::int16_t()) : get(std::uint16_t());
    case 4:
        if (type.floating)
            return get(float());
        return type.is_signed ? get(std::int32_t()) : get(std::uint32_t());
    default:
        return get(double());
    }
}

/// Parses one ASCII token as a number of `type`.
bool parse_ascii(std::string_view token, const PlyType& type, double& value, long long& integer) {
    if (type.floating)
        return parse_finite(token, value);
    if (!parse_integer(token, integer))
        return false;
    const int bits = 8 * type.size;
    const long long lo = type.is_signed ? -(1LL << (bits - 1)) : 0;
    const long long hi = type.is_signed ? (1LL << (bits - 1)) - 1 : (1LL << bits) - 1;
    value = double(integer);
    return integer >= lo && integer <= hi;
}

std::vector<PlyElement> parse_header(
    const std::string& path, TextCursor& text, bool& binary, bool& big_endian) {
    std::string_view line;
    if (!text.next_line(line) || split_tokens(line).empty() || split_tokens(line)[0] != "ply")
        throw FileError(path, 1, "not a PLY file (the first line is not 'ply')");
    if (!text.next_line(line))
        throw FileError(path, 1, "file ends before the PLY format line");
    std::vector<std::string_view> tokens = split_tokens(line);
    if (tokens.size() < 3 || tokens[0] != "format"
        || (tokens[1] != "ascii" && tokens[1] != "binary_little_endian"
            && tokens[1] != "binary_big_endian"))
        throw FileError(path, text.line(),
            "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
    binary = tokens[1] != "ascii";
    big_endian = tokens[1] == "binary_big_endian";
    std::vector<PlyElement> elements;
    for (;;) {
        if (!text.next_line(line))
            throw FileError(path, text.line(), "file ends inside the header (no 'end_header')");
        tokens = split_tokens(line);
        if (tokens.empty())
            throw FileError(path, text.line(), "empty line in the header");
        if (tokens[0] == "end_header")
            break;
        if (tokens[0] == "element") {
            long long count = 0;
            if (tokens.size() < 3 || !parse_integer(tokens[2], count) || count < 0)
                throw FileError(path, text.line(), "expected 'element <name> <count>'");
            elements.push_back({ std::string(tokens[1]), count, text.line(), {} });
        } else if (tokens[0] == "property") {
            if (elements.empty())
                throw FileError(path, text.line(), "property before any element");
            PlyElement& e = elements.back();
            PlyProperty p;
            const bool list = tokens.size() >= 2 && tokens[1] == "list";
            if (tokens.size() < (list ? 5u : 3u))
                throw FileError(path, text.line(),
                    "expected 'property <type> <name>' or 'property list <count type> <type> "
                    "<name>'");
            p.name = std::string(tokens[list ? 4 : 2]);
            p.type = find_type(tokens[list ? 3 : 1]);
            if (list)
                p.count_type = find_type(tokens[2]);
            if (!p.type || (list && !p.count_type))
                throw FileError(path, text.line(), "unknown PLY type in " + quote(line));
            if (list && p.count_type->floating)
                throw FileError(path, text.line(), "list count type must be an integer type");
            if (e.is_vertex() && (p.name == "x" || p.name == "y" || p.name == "z")) {
                if (list || !p.type->floating)
                    throw FileError(path, text.line(),
                        "vertex coordinate " + p.name + " must be float or double");
                p.role = Role::Coordinate;
            }
            if (e.is_face() && (p.name == "vertex_indices" || p.name == "vertex_index") && list) {
                if (p.type->floating || p.type->size != 4)
                    throw FileError(
                        path, text.line(), p.name + " items must be int or uint (what CGAL reads)");
                p.role = Role::Indices;
            }
            // CGAL reads a halfedge's source and target as uint without checking the type.
            if (e.name == "halfedge" && (p.name == "source" || p.name == "target")
                && (list || p.type->name != "uint"))
                throw FileError(path, text.line(), "halfedge " + p.name + " must be uint");
            e.properties.push_back(std::move(p));
        }
        // comment, obj_info and other keywords: ignored, as CGAL does
    }
    for (const PlyElement& e : elements) {
        if (e.count > 0 && e.properties.empty())
            throw FileError(path, e.line, "element " + quote(e.name) + " has no properties");
        int coordinates = 0;
        bool indices = false;
        for (const PlyProperty& p : e.properties) {
            coordinates += p.role == Role::Coordinate;
            indices = indices || p.role == Role::Indices;
        }
        if (e.is_vertex() && coordinates != 3)
            throw FileError(path, e.line, "vertex element needs float x, y and z properties");
        if (e.is_face() && !indices)
            throw FileError(path, e.line,
                "face element needs a list property vertex_indices (int or uint items)");
    }
    return elements;
}

} // namespace

SurfaceScan scan_ply(const std::string& path, std::string_view bytes) {
    TextCursor text(bytes);
    bool binary = false, big_endian = false;
    const std::vector<PlyElement> elements = parse_header(path, text, binary, big_endian);
    SurfaceScan scan;
    scan.binary = binary;
    scan.vertices = 0;
    for (const PlyElement& e : elements)
        if (e.is_vertex())
            scan.vertices += long(e.count);
    ByteCursor in(bytes, text.position(), big_endian);
    // Every value takes >= 1 byte in binary, >= 2 ("0 ") in ASCII.
    const std::size_t min_value_bytes = binary ? 1 : 2;
    for (const PlyElement& e : elements) {
        if (e.properties.empty())
            continue; // count 0, checked with the header
        const std::size_t left = binary ? in.remaining() : text.remaining();
        if (std::size_t(e.count) > left / (min_value_bytes * e.properties.size()) + 1)
            throw FileError(path, e.line,
                "element " + quote(e.name) + " declares " + std::to_string(e.count)
                    + " items but only " + std::to_string(left) + " bytes follow the header");
        for (long long item = 0; item < e.count; ++item) {
            const std::size_t item_at = binary ? in.position() : 0;
            auto fail = [&](const std::string& what) -> FileError {
                const std::string msg = e.name + " " + std::to_string(item) + ": " + what;
                return binary ? byte_error(path, in.position(), msg)
                              : FileError(path, text.token_line, msg);
            };
            auto value = [&](const PlyType& type, double& v, long long& i) {
                if (binary) {
                    if (!read_binary(in, type, v, i))
                        throw fail("file ends inside it");
                    return;
                }
                std::string_view token;
                if (!text.next_token(token))
                    throw fail("file ends inside it");
                if (!parse_ascii(token, type, v, i))
                    throw fail(quote(token) + " is not a " + std::string(type.name));
            };
            for (const PlyProperty& p : e.properties) {
                double v = 0;
                long long i = 0;
                if (!p.count_type) {
                    value(*p.type, v, i);
                    if (p.role == Role::Coordinate && !std::isfinite(v))
                        throw fail("coordinate " + p.name + " is not finite");
                    continue;
                }
                value(*p.count_type, v, i);
                const long list_at = binary ? long(item_at) : text.token_line;
                const std::size_t room = binary ? in.remaining() / std::size_t(p.type->size)
                                                : text.remaining() / 2 + 1;
                if (i < 0 || std::size_t(i) > room)
                    throw fail("list " + p.name + " declares " + std::to_string(i)
                        + " items, more than the file holds");
                if (p.role == Role::Indices && (i < 3 || i > kMaxPolygonVertices))
                    throw fail("face has " + std::to_string(i) + " vertices (3 to "
                        + std::to_string(kMaxPolygonVertices) + ")");
                const long long n = i;
                for (long long k = 0; k < n; ++k) {
                    value(*p.type, v, i);
                    if (p.role == Role::Indices && (i < 0 || i >= scan.vertices))
                        throw fail("vertex id " + std::to_string(i) + " is out of range [0, "
                            + std::to_string(scan.vertices) + ")");
                }
                if (p.role == Role::Indices) {
                    scan.polygon_at.push_back(list_at);
                    scan.corners += long(n);
                    ++scan.polygons;
                }
            }
        }
    }
    if (scan.polygons == 0)
        throw FileError(path, 0, "no faces");
    return scan;
}

} // namespace polycut::meshing::detail

// OBJ writer for triangle surfaces ("v x y z" and 1-based "f a b c" lines).
#include "polycut/mesh/io_obj.hpp"

#include "io_write.hpp"
#include "polycut/common/error.hpp"

namespace polycut::mesh {
namespace {
template <class Position, class Triangle>
void write_obj_impl(const std::string& path, Index num_vertices, Index num_triangles,
    Position&& position, Triangle&& triangle) {
    std::string out = "# polycut surface: " + std::to_string(num_vertices) + " vertices, "
        + std::to_string(num_triangles) + " triangles\n";
    out.reserve(out.size() + std::size_t(num_vertices) * 64 + std::size_t(num_triangles) * 32);
    for (Index v = 0; v < num_vertices; ++v) {
        const Vec3 p = position(v);
        out += 'v';
        for (int k = 0; k < 3; ++k) {
            out += ' ';
            io::append_number(out, p[k]);
        }
        out += '\n';
    }
    for (Index t = 0; t < num_triangles; ++t) {
        const std::array<Index, 3> tri = triangle(t);
        out += 'f';
        for (Index i : tri) {
            if (i < 0 || i >= num_vertices)
                throw InputError("triangles/" + std::to_string(t),
                    "vertex index " + std::to_string(i) + " out of range [0, "
                        + std::to_string(num_vertices) + ")");
            out += ' ';
            io::append_number(out, long(i) + 1);
        }
        out += '\n';
    }
    io::write_file(path, out);
}
} // namespace

void write_obj(const std::string& path, const MatX3& positions, const MatX3i& triangles) {
    write_obj_impl(
        path, Index(positions.rows()), Index(triangles.rows()),
        [&](Index v) { return Vec3(positions.row(v).transpose()); },
        [&](Index t) {
            return std::array<Index, 3> { triangles(t, 0), triangles(t, 1), triangles(t, 2) };
        });
}

void write_obj(const std::string& path, const std::vector<Vec3>& positions,
    const std::vector<std::array<Index, 3>>& triangles) {
    write_obj_impl(
        path, Index(positions.size()), Index(triangles.size()),
        [&](Index v) { return positions[std::size_t(v)]; },
        [&](Index t) { return triangles[std::size_t(t)]; });
}

} // namespace polycut::mesh

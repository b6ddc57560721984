// Surface helpers without CGAL: the boundary of a volume mesh as a triangle surface, and the
// volume a closed surface encloses.
#include "polycut/meshing/surface.hpp"

#include <cstddef>

namespace polycut::meshing {

SurfaceMesh boundary_surface(const mesh::Mesh& m) {
    const std::vector<Index> faces = m.boundary_faces();
    std::vector<Index> id(m.rest.size(), kNone);
    for (Index f : faces)
        for (Index n : m.faces[std::size_t(f)].nodes)
            id[std::size_t(n)] = 0;
    SurfaceMesh s;
    for (std::size_t n = 0; n < id.size(); ++n)
        if (id[n] == 0) {
            id[n] = Index(s.positions.size());
            s.positions.push_back(m.rest[n]);
        }
    for (Index f : faces) {
        // A boundary face's loop is outward for its owner, the only cell it has.
        const std::vector<Index>& loop = m.faces[std::size_t(f)].nodes;
        for (std::size_t k = 1; k + 1 < loop.size(); ++k)
            s.triangles.push_back({ id[std::size_t(loop[0])], id[std::size_t(loop[k])],
                id[std::size_t(loop[k + 1])] });
    }
    return s;
}

double enclosed_volume(const SurfaceMesh& s) {
    // Divergence theorem: V = 1/6 sum over triangles of a . (b x c).
    double six_v = 0;
    for (const auto& t : s.triangles) {
        const Vec3& a = s.positions[std::size_t(t[0])];
        const Vec3& b = s.positions[std::size_t(t[1])];
        const Vec3& c = s.positions[std::size_t(t[2])];
        six_v += a.dot(b.cross(c));
    }
    return six_v / 6;
}

} // namespace polycut::meshing

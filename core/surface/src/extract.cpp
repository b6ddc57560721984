#include "polycut/surface/extract.hpp"

#include "polycut/geometry/polygon.hpp"

#include <unordered_map>

namespace polycut::surface {

Topology extract_topology(const mesh::Mesh& mesh) {
    Topology topo;
    std::vector<Index> vertex_of(mesh.rest.size(), kNone);
    auto vertex = [&](Index node) {
        Index& v = vertex_of[std::size_t(node)];
        if (v == kNone) {
            v = Index(topo.vertex_nodes.size());
            topo.vertex_nodes.push_back(node);
        }
        return std::uint32_t(v);
    };
    std::vector<Vec3> points;
    for (Index f = 0; f < mesh.num_faces(); ++f) {
        const mesh::Face& face = mesh.faces[std::size_t(f)];
        if (!face.boundary())
            continue;
        const auto& loop = face.nodes; // outward for the owner, the only cell of a boundary face
        const std::uint8_t tag
            = std::uint8_t(face.tag == mesh::FaceTag::Cut ? Tag::Cut : Tag::Skin);
        const Vec3& a = mesh.rest[std::size_t(loop[0])];
        // This runs over every boundary face at every cut: a triangle needs no area, and the
        // points of a larger loop go into one reused buffer.
        double scale = 0;
        if (loop.size() > 3) {
            points.clear();
            for (Index n : loop)
                points.push_back(mesh.rest[std::size_t(n)]);
            scale = geometry::polygon_area(points);
        }
        for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
            const Vec3& b = mesh.rest[std::size_t(loop[i])];
            const Vec3& c = mesh.rest[std::size_t(loop[i + 1])];
            // Skip fan triangles over collinear nodes (hanging nodes on an edge).
            if (loop.size() > 3 && 0.5 * (b - a).cross(c - a).norm() <= 1e-12 * scale)
                continue;
            topo.triangles.insert(
                topo.triangles.end(), { vertex(loop[0]), vertex(loop[i]), vertex(loop[i + 1]) });
            topo.tags.push_back(tag);
            topo.triangle_faces.push_back(f);
        }
    }
    return topo;
}

void gather_positions(
    const Topology& topo, const std::vector<Vec3>& node_positions, std::vector<float>& out) {
    out.resize(topo.vertex_nodes.size() * 3);
    for (std::size_t v = 0; v < topo.vertex_nodes.size(); ++v) {
        const Vec3& p = node_positions[std::size_t(topo.vertex_nodes[v])];
        out[3 * v + 0] = float(p.x());
        out[3 * v + 1] = float(p.y());
        out[3 * v + 2] = float(p.z());
    }
}

bool is_closed_oriented(const Topology& topo) {
    // Directed edge counts: each directed edge once, and its reverse once.
    std::unordered_map<std::uint64_t, int> directed;
    auto key = [](std::uint32_t a, std::uint32_t b) { return (std::uint64_t(a) << 32) | b; };
    for (std::size_t t = 0; t + 2 < topo.triangles.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const auto a = topo.triangles[t + std::size_t(k)];
            const auto b = topo.triangles[t + std::size_t((k + 1) % 3)];
            if (++directed[key(a, b)] > 1)
                return false;
        }
    for (const auto& [k, n] : directed) {
        const auto a = std::uint32_t(k >> 32), b = std::uint32_t(k & 0xffffffffu);
        if (!directed.count(key(b, a)))
            return false;
    }
    return true;
}

} // namespace polycut::surface

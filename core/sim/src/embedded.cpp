// sim::Simulation: the embedded detailed surface (issue 15 item 2). The scene's surface file is
// embedded in the simulation mesh (embed::embed_surface, the cells' own bases); the stream, the
// renderer and contact use it instead of the mesh's boundary. After a cut it is embedded in the
// cut mesh again (its vertices follow the piece their rest position lies in) and the cut lips
// of the mesh (tag 2) are streamed with it; the embedded skin itself is not split.
#include "impl.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/contact/contact_field.hpp"
#include "polycut/embed/embedding.hpp"
#include "polycut/meshing/surface.hpp"
#include "setup.hpp"

#include <filesystem>

namespace polycut::sim {

void Simulation::Impl::build_embedded() {
    embedded.reset();
    if (!scene.embedded)
        return;
    const std::filesystem::path path
        = std::filesystem::path(scene.directory) / scene.embedded->path;
    meshing::SurfaceMesh surface;
    try {
        surface = meshing::read_surface(path.string(), false);
    } catch (const FileError& e) {
        throw SceneError("/embedded/path", e.what());
    }
    for (Vec3& p : surface.positions)
        p *= scene.embedded->scale;
    embedded_triangles = surface.triangles;
    const Stopwatch watch;
    embedded = std::make_unique<embed::Embedding>(embed::embed_surface(
        mesh, std::move(surface.positions), embedded_triangles, basis_options(scene).poly));
    embed_ms = watch.ms();
    lip_vertex_nodes.clear();
    lip_triangles.clear();
    embedded_version = topology_version;
}

void Simulation::Impl::refresh_embedded() {
    if (!embedded || embedded_version == topology_version)
        return;
    const Stopwatch watch;
    std::vector<Vec3> rest = embedded->rest;
    *embedded = embed::embed_surface(
        mesh, std::move(rest), embedded_triangles, basis_options(scene).poly);
    // The lips: the mesh's Cut triangles over their own vertices.
    lip_vertex_nodes.clear();
    lip_triangles.clear();
    std::vector<std::uint32_t> vertex_of(topology.vertex_nodes.size(), ~0u);
    for (std::size_t t = 0; t < topology.tags.size(); ++t) {
        if (topology.tags[t] != std::uint8_t(surface::Tag::Cut))
            continue;
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = topology.triangles[3 * t + std::size_t(k)];
            if (vertex_of[v] == ~0u) {
                vertex_of[v] = std::uint32_t(lip_vertex_nodes.size());
                lip_vertex_nodes.push_back(topology.vertex_nodes[v]);
            }
            lip_triangles.push_back(vertex_of[v]);
        }
    }
    embedded_version = topology_version;
    embed_ms = watch.ms();
}

bool Simulation::Impl::embedded_current() const {
    return embedded && embedded_version == topology_version;
}

void Simulation::Impl::embedded_positions(std::vector<float>& out) const {
    embed::deform(*embedded, positions, out);
    out.reserve(out.size() + 3 * lip_vertex_nodes.size());
    for (const Index n : lip_vertex_nodes)
        for (int k = 0; k < 3; ++k)
            out.push_back(float(positions[std::size_t(n)][k]));
}

void Simulation::Impl::embedded_surface(Surface& out) const {
    out.topology_version = topology_version;
    embedded_positions(out.positions);
    out.triangles = embedded->triangles;
    out.tags.assign(embedded->triangles.size() / 3, std::uint8_t(surface::Tag::Skin));
    const auto offset = std::uint32_t(embedded->rest.size());
    for (const std::uint32_t v : lip_triangles)
        out.triangles.push_back(v + offset);
    out.tags.resize(out.triangles.size() / 3, std::uint8_t(surface::Tag::Cut));
}

contact::Samples Simulation::Impl::embedded_samples() const {
    // Embedded vertices with their weights and a third of the area of their triangles, then
    // the lips' nodes.
    contact::Samples out;
    const embed::Embedding& e = *embedded;
    std::vector<double> area(e.rest.size(), 0.0);
    for (std::size_t t = 0; t + 2 < e.triangles.size(); t += 3) {
        const Vec3& a = e.rest[e.triangles[t]];
        const Vec3& b = e.rest[e.triangles[t + 1]];
        const Vec3& c = e.rest[e.triangles[t + 2]];
        const double third = (b - a).cross(c - a).norm() / 6.0;
        for (int k = 0; k < 3; ++k)
            area[e.triangles[t + std::size_t(k)]] += third;
    }
    out.nodes = e.nodes;
    out.weights = e.weights;
    out.offsets = e.offsets;
    out.areas = area;
    out.triangles = e.triangles;
    const contact::Samples lips = contact::node_samples(mesh.rest, lip_vertex_nodes, lip_triangles);
    const auto first = std::uint32_t(out.areas.size());
    for (std::size_t s = 0; s < lips.size(); ++s) {
        for (std::uint32_t k = lips.offsets[s]; k < lips.offsets[s + 1]; ++k) {
            out.nodes.push_back(lips.nodes[k]);
            out.weights.push_back(lips.weights[k]);
        }
        out.offsets.push_back(std::uint32_t(out.nodes.size()));
        out.areas.push_back(lips.areas[s]);
    }
    for (const std::uint32_t v : lips.triangles)
        out.triangles.push_back(first + v);
    return out;
}

} // namespace polycut::sim

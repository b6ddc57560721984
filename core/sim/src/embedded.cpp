// sim::Simulation: the embedded detailed surface (issue 15 item 2). The scene's surface file is
// embedded in the simulation mesh (embed::embed_surface, the cells' own bases); the stream, the
// renderer and contact use it instead of the mesh's boundary. A cut splits it along the blade
// (embed::split_along_cut, decision 0033): near the new Cut faces only, the skin triangles are
// split by them, the vertices on the cut get one copy per side, and the Cut faces clipped to
// the inside of the detailed surface close it as tag 2 lips. Vertices whose cells the cut
// changed are embedded again; the rest keep their weights. After the undo of a cut (or a reset)
// the surface is embedded anew and split along all the mesh's Cut faces.
#include "impl.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/contact/contact_field.hpp"
#include "polycut/contact/triangle_mesh_distance.hpp"
#include "polycut/embed/embedding.hpp"
#include "polycut/embed/split.hpp"
#include "polycut/meshing/surface.hpp"
#include "setup.hpp"

#include <algorithm>
#include <filesystem>
#include <utility>

namespace polycut::sim {

void Simulation::Impl::build_embedded() {
    embedded.reset();
    embedded_split.reset();
    embedded_base.reset();
    embedded_inside.reset();
    embedded_pending_cut = nullptr;
    embedded_stats = {};
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
    embedded_loaded_vertices = embedded->rest.size();
    embedded_base = std::make_unique<embed::Embedding>(*embedded);
    embedded_split = std::make_unique<embed::SplitState>();
    embed_ms = watch.ms();
    lip_vertex_nodes.clear();
    lip_triangles.clear();
    embedded_version = topology_version;
    embedded_stats.embed_ms = embed_ms;
    embedded_stats.full = true;
}

void Simulation::Impl::note_embedding_cut(const cut::CutReport& report) {
    embedded_pending_cut = &report;
}

bool Simulation::Impl::split_embedded(const embed::CutChange& change) {
    try {
        if (!embedded_inside) {
            // The lips are the cut inside the surface as loaded (rest space).
            std::vector<Vec3> rest(embedded->rest.begin(),
                embedded->rest.begin() + std::ptrdiff_t(embedded_loaded_vertices));
            embedded_inside = std::make_unique<contact::TriangleMeshDistance>(
                std::move(rest), embedded_triangles);
        }
        const contact::TriangleMeshDistance& inside = *embedded_inside;
        const embed::SplitReport r = embed::split_along_cut(
            *embedded, *embedded_split, mesh, change,
            [&inside](const Vec3& X) {
                Vec3 n;
                return inside.signed_distance(X, n) < 0;
            },
            basis_options(scene).poly);
        if (r.overlaps_earlier_cut)
            return false; // the caller splits anew along all the Cut faces (decision 0033)
        embedded_stats.split_ms = r.total_ms;
        embedded_stats.corefine_ms = r.corefine_ms;
        embedded_stats.patch_triangles = r.patch_triangles;
        embedded_stats.cut_triangles = r.cut_triangles;
        embedded_stats.reembedded = r.reembedded;
        return true;
    } catch (const Error&) {
        // CGAL could not corefine (or the inside test could not be built): the surface as
        // loaded, unsplit, with the mesh's own Cut faces as lips (decision 0031's behaviour).
        embedded_stats.split = false;
        return false;
    }
}

void Simulation::Impl::refresh_embedded() {
    const cut::CutReport* cut = std::exchange(embedded_pending_cut, nullptr);
    // A cut always refreshes: after a failed cut was undone within the same tick, the next
    // cut's topology version can equal the one the embedding was last made for.
    if (!embedded || (embedded_version == topology_version && cut == nullptr))
        return;
    const Stopwatch watch;
    const basis::PolyBasis poly = basis_options(scene).poly;
    const bool follows
        = cut != nullptr && embedded_version + 1 == topology_version && cut->node_map.empty();
    // The unsplit surface follows the cut where it changed cells; anything else (an undo, a
    // reset, node ids renumbered) embeds it anew.
    // An embedding's vertices follow the cut's cell map; those in changed (or merged-away)
    // cells are returned, to be embedded again.
    auto moved_by_cut = [&cut](embed::Embedding& e) {
        std::vector<std::uint32_t> moved;
        const std::vector<Index>& changed = cut->changed_cells;
        for (std::size_t v = 0; v < e.cells.size(); ++v) {
            Index c = e.cells[v];
            if (!cut->cell_map.empty() && c != kNone && std::size_t(c) < cut->cell_map.size())
                c = e.cells[v] = cut->cell_map[std::size_t(c)];
            if (c == kNone || std::binary_search(changed.begin(), changed.end(), c))
                moved.push_back(std::uint32_t(v));
        }
        return moved;
    };
    if (follows) {
        embed::reembed(*embedded_base, mesh, moved_by_cut(*embedded_base), poly);
    } else {
        std::vector<Vec3> rest(embedded->rest.begin(),
            embedded->rest.begin() + std::ptrdiff_t(embedded_loaded_vertices));
        *embedded_base = embed::embed_surface(mesh, std::move(rest), embedded_triangles, poly);
    }
    bool local = follows && embedded_stats.split;
    if (local) {
        // Only what this cut changed: vertices in changed (or merged-away) cells are embedded
        // again, and the surface is split along the new Cut faces.
        local = split_embedded({ cut->cut_faces, cut->duplicated, moved_by_cut(*embedded) });
        embedded_stats.full = false;
    }
    if (!local) {
        // Anew: the surface as loaded, then split along every Cut face of the mesh.
        *embedded = *embedded_base;
        embedded_split = std::make_unique<embed::SplitState>();
        embedded_stats.full = true;
        std::vector<Index> cut_faces;
        for (Index f = 0; f < mesh.num_faces(); ++f)
            if (mesh.faces[std::size_t(f)].boundary()
                && mesh.faces[std::size_t(f)].tag == mesh::FaceTag::Cut)
                cut_faces.push_back(f);
        if (!cut_faces.empty() && embedded_stats.split
            && !split_embedded({ std::move(cut_faces), {}, {} })) {
            *embedded = *embedded_base;
        }
    }
    // Without the split (a CGAL failure): the lips are the mesh's Cut triangles over their own
    // vertices.
    lip_vertex_nodes.clear();
    lip_triangles.clear();
    if (!embedded_stats.split) {
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
    }
    embedded_version = topology_version;
    embed_ms = watch.ms();
    embedded_stats.embed_ms = embed_ms;
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
    const std::size_t n = embedded->triangles.size() / 3;
    out.tags.assign(n, std::uint8_t(surface::Tag::Skin));
    for (std::size_t t = 0; t < std::min(n, embedded->lip.size()); ++t)
        if (embedded->lip[t])
            out.tags[t] = std::uint8_t(surface::Tag::Cut);
    const auto offset = std::uint32_t(embedded->rest.size());
    for (const std::uint32_t v : lip_triangles)
        out.triangles.push_back(v + offset);
    out.tags.resize(out.triangles.size() / 3, std::uint8_t(surface::Tag::Cut));
}

EmbeddedStats Simulation::embedded_stats() const {
    const Impl& s = *m_impl;
    if (!s.embedded)
        return {};
    EmbeddedStats out = s.embedded_stats;
    out.vertices = s.embedded->rest.size() + s.lip_vertex_nodes.size();
    out.triangles = (s.embedded->triangles.size() + s.lip_triangles.size()) / 3;
    out.lip_triangles = s.lip_triangles.size() / 3;
    for (const std::uint8_t l : s.embedded->lip)
        out.lip_triangles += l;
    return out;
}

contact::Samples Simulation::Impl::embedded_samples() const {
    // Embedded vertices (the skin's and, once cut, the lips') with their weights and a third
    // of the area of their triangles; then the mesh's lip nodes when the split failed.
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

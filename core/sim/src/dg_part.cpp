// The DG side of sim::Simulation (dg_part.hpp).
#include "dg_part.hpp"

#include "polycut/common/error.hpp"
#include "polycut/cut/cutter.hpp"
#include "polycut/dg/refine.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "setup.hpp"

#include <Eigen/Dense>
#include <algorithm>

namespace polycut::sim {

dg::DgOptions dg_options(const scene::Scene& s) {
    dg::DgOptions o;
    o.degree = s.basis.degree;
    o.flux = s.dg.flux;
    o.penalty = s.dg.penalty;
    o.dirichlet_penalty = s.dg.dirichlet_penalty;
    o.lambda_penalty = s.dg.lambda_penalty;
    return o;
}

namespace {
/// Whether the region selects every node of a boundary face.
bool face_selected(const scene::Selector& where, const mesh::Mesh& m, const mesh::Face& face) {
    return std::all_of(face.nodes.begin(), face.nodes.end(),
        [&](Index n) { return scene::selects(where, m.rest[std::size_t(n)]); });
}
} // namespace

DgDirichlet dg_dirichlet_faces(const scene::Scene& s, const mesh::Mesh& m) {
    DgDirichlet out;
    for (std::size_t i = 0; i < s.fixed.size(); ++i) {
        const scene::Fixed& fx = s.fixed[i];
        const std::string where = "/fixed/" + std::to_string(i);
        if (fx.at_node)
            throw SceneError(where,
                "method \"dg\" imposes fixed regions weakly on boundary faces; a single node "
                "cannot be fixed (select a region)");
        const std::uint8_t axes = std::uint8_t(
            (fx.components[0] ? 1 : 0) | (fx.components[1] ? 2 : 0) | (fx.components[2] ? 4 : 0));
        Index count = 0;
        for (Index f = 0; f < m.num_faces(); ++f) {
            const mesh::Face& face = m.faces[std::size_t(f)];
            if (face.boundary() && face_selected(fx.where, m, face)) {
                out.faces.push_back(f);
                out.axes.push_back(axes);
                ++count;
            }
        }
        if (count == 0)
            throw SceneError(where,
                "selects no boundary face of the mesh (method \"dg\" fixes the boundary faces "
                "whose nodes the region selects)");
    }
    return out;
}

namespace {
VecX dg_scene_loads(const scene::Scene& s, const mesh::Mesh& m, const dg::DgModel& model,
    const dg::Stitching& stitching) {
    VecX out = VecX::Zero(3 * model.num_coefficients());
    // Point and uniform forces act on nodes: through the stitching's adjoint.
    scene::Scene nodal = s;
    nodal.loads.forces.clear();
    nodal.loads.pressures.clear();
    for (const scene::Force& f : s.loads.forces)
        if (f.kind == scene::Force::Kind::Point || f.distribution == scene::Distribution::Uniform)
            nodal.loads.forces.push_back(f);
    if (!nodal.loads.forces.empty()) {
        VecX c;
        stitching.loads(scene_loads(nodal, m), c);
        out += c;
    }
    // Area forces: a uniform traction F / A on the selected boundary faces; pressures: -p n.
    for (std::size_t i = 0; i < s.loads.forces.size(); ++i) {
        const scene::Force& f = s.loads.forces[i];
        if (f.kind == scene::Force::Kind::Point || f.distribution == scene::Distribution::Uniform)
            continue;
        std::vector<Index> faces;
        double area = 0;
        for (Index k = 0; k < m.num_faces(); ++k) {
            const mesh::Face& face = m.faces[std::size_t(k)];
            if (!face.boundary() || !face_selected(f.region, m, face))
                continue;
            faces.push_back(k);
            area += geometry::polygon_area(geometry::gather(m.rest, face.nodes));
        }
        if (!(area > 0))
            throw SceneError("/loads/forces/" + std::to_string(i),
                "selects no boundary face of the mesh (\"area\" distribution)");
        out += model.traction_load(faces, f.force / area);
    }
    for (std::size_t i = 0; i < s.loads.pressures.size(); ++i) {
        const scene::Pressure& pr = s.loads.pressures[i];
        long count = 0;
        for (Index k = 0; k < m.num_faces(); ++k) {
            const mesh::Face& face = m.faces[std::size_t(k)];
            if (!face.boundary() || !face_selected(pr.region, m, face))
                continue;
            ++count;
            const Vec3 n = geometry::polygon_normal(geometry::gather(m.rest, face.nodes));
            out += model.traction_load({ k }, -pr.pressure * n);
        }
        if (count == 0)
            throw SceneError(
                "/loads/pressure/" + std::to_string(i), "selects no boundary face of the mesh");
    }
    return out;
}
} // namespace

std::unique_ptr<DgPart> make_dg_part(const scene::Scene& s, const mesh::Mesh& m,
    const dg::DgModel* old, const std::vector<Index>& source,
    const std::vector<std::uint8_t>& unchanged) {
    auto part = std::make_unique<DgPart>();
    DgDirichlet fixed = dg_dirichlet_faces(s, m);
    if (old)
        part->model = std::make_unique<dg::DgModel>(
            *old, m, source, unchanged, std::move(fixed.faces), std::move(fixed.axes));
    else
        part->model = std::make_unique<dg::DgModel>(m, elasticity_material(s), dg_options(s),
            std::move(fixed.faces), std::move(fixed.axes));
    part->stitching = std::make_unique<dg::Stitching>(*part->model);
    part->scene_load = dg_scene_loads(s, m, *part->model, *part->stitching);
    return part;
}

std::unique_ptr<DgPart> dg_after_cut(const DgPart& old, const scene::Scene& s, const mesh::Mesh& m,
    const cut::CutReport& report, MatX3& x, MatX3& v) {
    const dg::DgModel& om = *old.model;
    // Source (old id) of every cell of the edited mesh.
    const Index n_cells = m.num_cells();
    std::vector<Index> source(std::size_t(n_cells), kNone);
    if (report.cell_map.empty()) {
        for (Index c = 0; c < std::min(n_cells, report.cells_before); ++c)
            source[std::size_t(c)] = c;
    } else {
        for (std::size_t o = 0; o < report.cell_map.size(); ++o)
            if (const Index c = report.cell_map[o]; c != kNone && c < n_cells)
                source[std::size_t(c)] = Index(o);
    }
    for (const cut::CellOrigin& origin : report.new_cells)
        if (origin.cell >= 0 && origin.cell < n_cells)
            source[std::size_t(origin.cell)] = origin.parent;
    std::vector<std::uint8_t> unchanged(std::size_t(n_cells), 1);
    for (Index c : report.changed_cells)
        if (c >= 0 && c < n_cells)
            unchanged[std::size_t(c)] = 0;
    for (Index c = 0; c < n_cells; ++c)
        if (source[std::size_t(c)] == kNone)
            throw Error("cut", "cell " + std::to_string(c) + " has no cell it came from");
    // Only the cells and faces the cut changed are integrated again (issue 13 item 6).
    auto part = make_dg_part(s, m, &om, source, unchanged);
    const dg::DgModel& nm = *part->model;
    const MatX3 u = dg::transfer_field(om, x - om.rest(), nm, source, unchanged);
    v = dg::transfer_field(om, v, nm, source, unchanged);
    x = nm.rest() + u;
    return part;
}

std::unique_ptr<DgPart> dg_refine(
    const DgPart& old, const scene::Scene& s, mesh::Mesh& m, MatX3& x, MatX3& v) {
    const dg::DgModel& om = *old.model;
    std::vector<Vec3> direction;
    const std::vector<double> stress = dg::principal_stress(om, x, &direction);
    std::vector<Index> hexes, others;
    for (Index c = 0; c < om.num_cells(); ++c) {
        const int level = std::size_t(c) < old.level.size() ? old.level[std::size_t(c)] : 0;
        if (stress[std::size_t(c)] > s.dg.refine_stress && level < s.dg.refine_levels)
            (m.cells[std::size_t(c)].shape == mesh::CellShape::Hex ? hexes : others).push_back(c);
    }
    if (hexes.empty() && others.empty())
        return nullptr;
    // Hexes 1-to-8 (a new mesh; `source` maps its cells to the old ones).
    std::vector<Index> source(std::size_t(m.num_cells()));
    std::vector<std::uint8_t> child(std::size_t(m.num_cells()), 0);
    for (Index c = 0; c < m.num_cells(); ++c)
        source[std::size_t(c)] = c;
    if (!hexes.empty()) {
        dg::Refinement r = dg::refine_hexes(m, hexes);
        m = std::move(r.mesh); // `om` keeps its bases: the transfer needs nothing else of it
        source = std::move(r.source);
        child = std::move(r.child);
    }
    // Other cells 1-to-2 by the plane through their centroid perpendicular to the principal
    // direction (003 sec. 10), with core/cut's plane split (convex cells stay convex).
    if (!others.empty()) {
        std::vector<Index> where(std::size_t(om.num_cells()), kNone); // old id -> current id
        for (std::size_t c = 0; c < source.size(); ++c)
            if (!child[c])
                where[std::size_t(source[c])] = Index(c);
        cut::Cutter cutter(m);
        for (Index o : others) {
            const Index c = where[std::size_t(o)];
            if (c == kNone)
                continue;
            const Index cells[1] = { c };
            const cut::CutReport rep
                = cutter.split_by_plane(m.cell_centroid(c), direction[std::size_t(o)], cells);
            const std::vector<Index> source_before = source; // by ids before the call
            if (!rep.cell_map.empty()) {
                // Sliver merges renumbered cells: carry the maps over.
                std::vector<Index> s2(std::size_t(m.num_cells()), kNone);
                std::vector<std::uint8_t> c2(std::size_t(m.num_cells()), 0);
                for (std::size_t k = 0; k < rep.cell_map.size(); ++k)
                    if (const Index n = rep.cell_map[k]; n != kNone && n < m.num_cells()) {
                        s2[std::size_t(n)] = source[k];
                        c2[std::size_t(n)] = child[k];
                    }
                source = std::move(s2);
                child = std::move(c2);
                for (Index& w : where)
                    if (w != kNone)
                        w = w < Index(rep.cell_map.size()) ? rep.cell_map[std::size_t(w)] : kNone;
            }
            source.resize(std::size_t(m.num_cells()), kNone);
            child.resize(std::size_t(m.num_cells()), 0);
            for (const cut::CellOrigin& n : rep.new_cells) {
                if (n.cell < 0 || n.cell >= m.num_cells() || n.parent < 0
                    || std::size_t(n.parent) >= source_before.size())
                    continue;
                source[std::size_t(n.cell)] = source_before[std::size_t(n.parent)];
                child[std::size_t(n.cell)] = 1;
                const Index parent_now
                    = rep.cell_map.empty() ? n.parent : rep.cell_map[std::size_t(n.parent)];
                if (parent_now != kNone && parent_now < m.num_cells())
                    child[std::size_t(parent_now)] = 1;
            }
        }
    }
    for (Index c = 0; c < m.num_cells(); ++c)
        if (source[std::size_t(c)] == kNone)
            throw Error("refine", "cell " + std::to_string(c) + " has no cell it came from");
    auto part = make_dg_part(s, m);
    const dg::DgModel& nm = *part->model;
    const MatX3 u = dg::transfer_field(om, x - om.rest(), nm, source);
    v = dg::transfer_field(om, v, nm, source);
    x = nm.rest() + u;
    part->level.resize(std::size_t(nm.num_cells()));
    for (Index c = 0; c < nm.num_cells(); ++c) {
        const Index o = source[std::size_t(c)];
        const int before = std::size_t(o) < old.level.size() ? old.level[std::size_t(o)] : 0;
        part->level[std::size_t(c)] = before + (child[std::size_t(c)] ? 1 : 0);
    }
    return part;
}

Vec3 dg_point_displacement(const DgPart& dg, const MatX3& x, const Vec3& X) {
    const mesh::Mesh& m = dg.model->mesh();
    MatX3 u;
    dg.stitching->displacements(x, u);
    const Index near = nearest_node(m, X);
    geometry::Aabb box;
    for (const Vec3& p : m.rest)
        box.extend(p);
    if (near != kNone && (m.rest[std::size_t(near)] - X).norm() <= 1e-9 * box.diagonal())
        return u.row(near).transpose(); // 003 eq. 17
    const dg::MlsEmbedding mls(*dg.model, { X }); // 003 eq. 18-19
    MatX3 out;
    mls.displacements(u, out);
    return out.row(0).transpose();
}

} // namespace polycut::sim

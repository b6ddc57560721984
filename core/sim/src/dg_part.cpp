// The DG side of sim::Simulation (dg_part.hpp).
#include "dg_part.hpp"

#include "polycut/common/error.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"
#include "setup.hpp"

#include <algorithm>

namespace polycut::sim {

dg::DgOptions dg_options(const scene::Scene& s) {
    dg::DgOptions o;
    o.degree = s.basis.degree;
    o.flux = s.dg.flux == "bz" ? dg::Flux::BabuskaZlamal : dg::Flux::InteriorPenalty;
    o.penalty = s.dg.penalty;
    o.dirichlet_penalty = s.dg.dirichlet_penalty;
    o.lambda_penalty
        = s.dg.lambda_penalty == "normal" ? dg::LambdaPenalty::Normal : dg::LambdaPenalty::Full;
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
        if (f.kind == scene::Force::Kind::Point || f.distribution == "uniform")
            nodal.loads.forces.push_back(f);
    if (!nodal.loads.forces.empty()) {
        VecX c;
        stitching.loads(scene_loads(nodal, m), c);
        out += c;
    }
    // Area forces: a uniform traction F / A on the selected boundary faces; pressures: -p n.
    for (std::size_t i = 0; i < s.loads.forces.size(); ++i) {
        const scene::Force& f = s.loads.forces[i];
        if (f.kind == scene::Force::Kind::Point || f.distribution == "uniform")
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

std::unique_ptr<DgPart> make_dg_part(const scene::Scene& s, const mesh::Mesh& m) {
    auto part = std::make_unique<DgPart>();
    DgDirichlet fixed = dg_dirichlet_faces(s, m);
    part->model = std::make_unique<dg::DgModel>(
        m, elasticity_material(s), dg_options(s), std::move(fixed.faces), std::move(fixed.axes));
    part->stitching = std::make_unique<dg::Stitching>(*part->model);
    part->scene_load = dg_scene_loads(s, m, *part->model, *part->stitching);
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

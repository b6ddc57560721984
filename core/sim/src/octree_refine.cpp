// Stress-based refinement of an octree geometry while it runs (001 sec. 8, issue 15 item 3):
// after a step, every cell whose largest absolute principal stress exceeds the scene's
// threshold is split 1-to-8 (and its neighbours as 2:1 balance needs), the mesh is built again
// from the tree, and the state is carried over without a pop: nodes that existed keep their
// position and velocity; a new node takes the displacement and velocity its old cell's own
// basis interpolates at its rest position (Q1 in a hex, the polyhedral basis otherwise: the
// same weights an embedded surface uses, embed::embed_points). Forces and grabs follow their
// nodes. A cut ends refinement: its cells are no longer octree leaves.
#include "cell_stress.hpp"
#include "impl.hpp"
#include "octree_part.hpp"
#include "polycut/contact/contact_field.hpp"
#include "polycut/embed/embedding.hpp"
#include "setup.hpp"

#include <Eigen/Eigenvalues>
#include <map>

namespace polycut::sim {
namespace {
struct RestLess {
    bool operator()(const Vec3& a, const Vec3& b) const {
        return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    }
};

/// Largest absolute principal stress [Pa] (001 sec. 8).
double principal_stress(const Mat3& sigma) {
    return Eigen::SelfAdjointEigenSolver<Mat3>(sigma, Eigen::EigenvaluesOnly)
        .eigenvalues()
        .cwiseAbs()
        .maxCoeff();
}
} // namespace

void Simulation::Impl::build_octree() {
    octree.reset();
    const scene::Geometry& g = scene.geometry;
    if (g.kind != scene::Geometry::Kind::Octree || !(g.octree.refine_stress > 0) || dg)
        return;
    octree = make_octree(scene);
    octree->build_mesh(); // the same leaves as initial_mesh: cell c is leaf cell_leaves()[c]
    octree_version = topology_version;
}

int Simulation::Impl::refine_octree(StepReport& report) {
    if (!octree)
        return 0;
    if (octree_version != topology_version) { // cut: the cells are not the tree's leaves
        octree.reset();
        return 0;
    }
    sync_positions(); // the stress of the state this step reached
    const auto material = elasticity_material(scene);
    const double threshold = scene.geometry.octree.refine_stress;
    const std::vector<int> leaves = octree->cell_leaves();
    std::vector<int> split;
    for (Index c = 0; c < mesh.num_cells(); ++c) {
        const int leaf = leaves[std::size_t(c)];
        if (octree->level(leaf) >= octree->max_depth())
            continue;
        const Mat3 sigma
            = cell_stress(material, scene.integrator.corotated, mesh, positions, c, nullptr);
        if (principal_stress(sigma) > threshold)
            split.push_back(leaf);
    }
    if (split.empty())
        return 0;
    report.refine_energy_before = energy().total();
    octree->refine(split);
    mesh::Mesh refined = octree->build_mesh();

    // State transfer: old nodes by rest position, new ones by their old cell's basis.
    std::map<Vec3, Index, RestLess> old_node;
    for (Index i = 0; i < mesh.num_nodes(); ++i)
        old_node.emplace(mesh.rest[std::size_t(i)], i);
    const Index n = refined.num_nodes();
    std::vector<Index> new_of_old(std::size_t(mesh.num_nodes()), kNone);
    std::vector<Index> fresh;
    std::vector<Vec3> fresh_rest;
    for (Index i = 0; i < n; ++i) {
        const auto it = old_node.find(refined.rest[std::size_t(i)]);
        if (it != old_node.end()) {
            new_of_old[std::size_t(it->second)] = i;
        } else {
            fresh.push_back(i);
            fresh_rest.push_back(refined.rest[std::size_t(i)]);
        }
    }
    const bool has_velocity = state.v.rows() == state.x.rows();
    MatX3 x(n, 3), v = MatX3::Zero(n, 3);
    for (Index i = 0; i < mesh.num_nodes(); ++i)
        if (const Index j = new_of_old[std::size_t(i)]; j != kNone) {
            x.row(j) = state.x.row(i);
            if (has_velocity)
                v.row(j) = state.v.row(i);
        }
    if (!fresh.empty()) {
        const embed::Embedding e
            = embed::embed_points(mesh, std::move(fresh_rest), basis_options(scene).poly);
        for (std::size_t k = 0; k < fresh.size(); ++k) {
            const Index j = fresh[k];
            Vec3 u = Vec3::Zero(), vel = Vec3::Zero();
            for (std::uint32_t w = e.offsets[k]; w < e.offsets[k + 1]; ++w) {
                const Index i = e.nodes[w];
                u += e.weights[w] * (state.x.row(i).transpose() - mesh.rest[std::size_t(i)]);
                if (has_velocity)
                    vel += e.weights[w] * state.v.row(i).transpose();
            }
            x.row(j) = (refined.rest[std::size_t(j)] + u).transpose();
            v.row(j) = vel.transpose();
        }
    }
    auto remap = [&](NodeWeights& at) {
        for (Index& node : at.nodes)
            node = new_of_old[std::size_t(node)];
    };
    for (auto& [id, f] : forces)
        remap(f.at);
    for (auto& [id, g] : grabs) {
        remap(g.at);
        g.offset_nodes.clear(); // node_offset is looked up again by rest position
    }

    mesh = std::move(refined);
    node_fixed_mask = fixed_dofs_from_scene(scene, mesh);
    scene_forces = scene_loads(scene, mesh);
    model = std::make_unique<elasticity::ElasticModel>(
        mesh, elasticity_material(scene), basis_options(scene), node_fixed_mask);
    initial_element_cost = element_cost(mesh); // what cuts grow from
    integrator = std::make_unique<integrate::Integrator>(*model, integrator_options(scene));
    if (contact)
        integrator->set_penalty_field(contact.get());
    const double state_time = state.time;
    state = integrator->rest_state();
    state.x = x;
    if (has_velocity)
        state.v = v;
    state.time = state_time;
    cutting.reset(); // its adjacency is of the old mesh
    cutting_prepared = false;
    static_solved = false;
    sync_positions();
    refresh_topology();
    octree_version = topology_version;
    report.cells_refined = int(split.size());
    report.refine_energy_after = energy().total();
    return int(split.size());
}

} // namespace polycut::sim

// Private: translating a scene's plain settings into the modules' option structs, and the
// scene's fixed sets and loads into per-DOF arrays.
#pragma once

#include "polycut/basis/cell_basis.hpp"
#include "polycut/elasticity/material.hpp"
#include "polycut/integrate/integrator.hpp"
#include "polycut/mesh/mesh.hpp"
#include "polycut/scene/scene.hpp"

#include <cstdint>
#include <vector>

namespace polycut::sim {

elasticity::Material elasticity_material(const scene::Scene& s);
basis::BasisOptions basis_options(const scene::Scene& s);
/// The integrator kind of a scene solver: type cholmod / cg_relaxation, or PCG with its
/// preconditioner.
integrate::LinearSolverKind linear_solver_kind(const scene::Solver& sv);
integrate::IntegratorOptions integrator_options(const scene::Scene& s);

/// Per-DOF fixed mask (3#N). Throws SceneError ("/fixed/i") for a set that selects no node.
std::vector<std::uint8_t> fixed_dofs_from_scene(const scene::Scene& s, const mesh::Mesh& m);

/// Constant nodal loads (3#N) [N] of the scene's forces (gravity is applied by the integrator).
/// Throws SceneError ("/loads/forces/i") for a region that selects no node.
VecX scene_loads(const scene::Scene& s, const mesh::Mesh& m);

/// Throws SceneError ("/integrator/dt") when the scene's integrator is semi-implicit Euler and
/// dt exceeds its stability limit on this model (integrate::semi_implicit_limit), naming it.
void check_time_step(const scene::Scene& s, const elasticity::ElasticModel& model);

/// What a step on the mesh costs, in entries of tet element matrices: the sum over cells of
/// (3 nodes)^2, a cell other than a tet weighted 4 (its entries are assembled by the general
/// kernel, and a cut polyhedron's nodes share fewer cells, so its entries add more stiffness
/// nonzeros per PCG iteration). What cutting.max_model_growth bounds (MeshStats::model_growth).
double element_cost(const mesh::Mesh& m);

/// What a cut call costs over the whole model whatever it cuts, in units of the tick's cut budget
/// (cutting.max_cells_per_tick): the stiffness pattern's update and the pipeline's passes are
/// O(cells). One unit per 200 cells (organ_5k, 26,400 cells: ~6 ms a call that changes a few
/// cells, 2.5 ms one that changes none; a budget unit ~0.045 ms; decision 0076).
Index cut_call_cost(const mesh::Mesh& m);

/// Node nearest to a rest-space point among nodes used by cells.
Index nearest_node(const mesh::Mesh& m, const Vec3& X);

} // namespace polycut::sim

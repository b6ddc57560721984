// sim::Simulation::build_report(): the parts build() measured (build_clock.hpp) with what they
// hold, and the parts made on demand (inertia, cut structures) with whether they exist yet.
#include "build_clock.hpp"
#include "impl.hpp"
#include "polycut/contact/contact_field.hpp"
#include "polycut/dg/dg_model.hpp"
#include "polycut/meshing/octree.hpp"

#include <cstdio>
#include <fstream>
#include <unistd.h>

namespace polycut::sim {

long resident_kb() {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    if (!(statm >> pages >> resident))
        return 0;
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

namespace {
BuildPart* part(std::vector<BuildPart>& parts, const std::string& name) {
    for (BuildPart& p : parts)
        if (p.name == name)
            return &p;
    parts.push_back({ name, false, 0, 0, "" });
    return &parts.back();
}

std::string counts(long tets, long hexes, long polyhedra) {
    return std::to_string(tets) + " tets, " + std::to_string(hexes) + " hexes, "
        + std::to_string(polyhedra) + " polyhedra";
}
} // namespace

BuildReport Simulation::build_report() const {
    const Impl& s = *m_impl;
    BuildReport r;
    r.parts = s.build_parts;
    const mesh::Mesh& m0 = s.initial_mesh;
    long tets = 0, hexes = 0, polyhedra = 0;
    for (const mesh::Cell& c : m0.cells)
        (c.shape == mesh::CellShape::Tet          ? tets
                : c.shape == mesh::CellShape::Hex ? hexes
                                                  : polyhedra)
            += 1;
    part(r.parts, "mesh")->detail = std::to_string(m0.num_nodes()) + " nodes, "
        + std::to_string(m0.num_cells()) + " cells (" + counts(tets, hexes, polyhedra) + ")"
        + (s.meshing.meshed ? ", meshed from " + s.meshing.source : std::string());
    const bool dynamic = s.scene.integrator.type != integrate::IntegratorKind::Static;
    if (s.model) {
        const auto& b = s.model->bases_built();
        r.p1_bases = b.p1;
        r.q1_bases = b.q1;
        r.polyhedral_bases = b.polyhedral;
        const char* poly = s.scene.method == scene::Method::Harmonic ? "harmonic" : "mean value";
        part(r.parts, "model")->detail = "bases: " + std::to_string(b.p1) + " P1, "
            + std::to_string(b.q1) + " Q1, " + std::to_string(b.polyhedral) + " polyhedral (" + poly
            + "); element stiffness, lumped nodal masses (gravity loads, picking), "
            + std::to_string(s.model->num_free_dofs()) + " free DOFs";
        BuildPart* inertia_part = part(r.parts, "inertia");
        inertia_part->built = s.model->inertia_built();
        inertia_part->detail = inertia_part->built
            ? "per-DOF lumped mass of the dynamic step, made at the first step"
            : dynamic ? "made at the first dynamic step"
                      : "not needed: static equilibrium has no inertia";
    } else if (s.dg) {
        r.dg_cells = long(s.mesh.num_cells());
        part(r.parts, "dg_model")->detail = std::to_string(s.mesh.num_cells()) + " cells of degree "
            + std::to_string(s.scene.basis.degree) + ", face terms, stitching; "
            + std::to_string(s.dg->model->num_free_dofs()) + " DOFs";
        BuildPart* inertia_part = part(r.parts, "inertia");
        inertia_part->built = true;
        inertia_part->detail = "the DG model's mass (part of dg_model)";
    }
    part(r.parts, "integrator")->detail = std::string(scene::to_string(s.scene.integrator.type))
        + ", solver " + scene::to_string(s.scene.solver.type)
        + (s.scene.solver.type == scene::SolverType::Pcg
                ? std::string(" + ") + scene::to_string(s.scene.solver.preconditioner)
                : std::string())
        + "; matrices and factors are set up at the first solve (inside the first step)";
    BuildPart* solver_part = part(r.parts, "solver");
    solver_part->detail = solver_part->built
        ? "the first step's AMG hierarchy, set up at load (Integrator::prepare)"
        : "nothing to set up ahead: the first solve sets up what its solver needs";
    part(r.parts, "surface")->detail = "boundary and cut triangles for streaming";
    BuildPart* contact_part = part(r.parts, "contact");
    contact_part->built = s.contact != nullptr;
    contact_part->detail = contact_part->built ? std::to_string(s.scene.obstacles.size())
            + " obstacles, " + std::to_string(s.tools.size()) + " tools"
                                               : "no obstacles, tools or self contact";
    BuildPart* embedded_part = part(r.parts, "embedded");
    embedded_part->built = s.embedded != nullptr;
    embedded_part->detail = embedded_part->built
        ? std::to_string(s.embedded_triangles.size()) + " triangles"
        : "no embedded surface";
    BuildPart* octree_part = part(r.parts, "octree");
    octree_part->built = s.octree != nullptr;
    octree_part->detail
        = octree_part->built ? "kept for stress refinement" : "no stress refinement";
    BuildPart* cut_part = part(r.parts, "cut");
    cut_part->built = s.cutting != nullptr;
    cut_part->detail = !cut_part->built
        ? "made at the first cut; none so far"
        : std::string("cut pipeline (") + scene::to_string(s.scene.cutting.method) + ")"
            + (s.cutting_prepared ? ", cutter adjacency, uncut grid and undo mirror prepared at "
                                    "load (prepare_cutting)"
                                  : ", made at the first cut");
    return r;
}

} // namespace polycut::sim

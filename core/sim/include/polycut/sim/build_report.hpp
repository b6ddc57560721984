// What a scene built and what each part cost (issue 17 item 6, DESIGN.md sec. 6 "model only what
// a scene requires"): sim::Simulation::build_report(). Parts a scene does not need are never
// built; parts built on demand (the inertia of a dynamic step, the cut structures of the first
// cut) say whether they have been built so far.
#pragma once

#include <string>
#include <vector>

namespace polycut::sim {

/// One part of the simulation a scene may build.
struct BuildPart {
    /// "mesh", "model" (bases, element stiffness, lumped nodal masses, sparsity pattern),
    /// "dg_model", "inertia", "integrator", "surface", "contact", "embedded", "octree", "cut"
    std::string name;
    bool built = false; ///< built so far (lazy parts: once something asked for them)
    /// Wall time of building it when the scene was loaded [ms]; 0 for a part built later on
    /// demand (its cost is inside the step or cut that needed it)
    double ms = 0;
    /// Resident memory added while building it [KiB] (RSS after - before; 0 when the allocator
    /// reused freed memory, so an estimate from below)
    long rss_kb = 0;
    std::string detail; ///< what was built, or why it was not
};

/// What a scene built, part by part, in build order.
struct BuildReport {
    std::vector<BuildPart> parts;
    /// Cell bases (shape functions and quadrature) computed so far, by basis: P1 for tets, Q1
    /// for hexes, the scene's polyhedral basis (mean value or harmonic) for other cells; counts
    /// the recomputations of cells a cut changed. DG cells (method dg) in dg_cells.
    long p1_bases = 0, q1_bases = 0, polyhedral_bases = 0, dg_cells = 0;

    /// The part named `name`, or null.
    const BuildPart* find(const std::string& name) const {
        for (const BuildPart& p : parts)
            if (p.name == name)
                return &p;
        return nullptr;
    }
    /// Whether the part named `name` exists and is built.
    bool built(const std::string& name) const {
        for (const BuildPart& p : parts)
            if (p.name == name)
                return p.built;
        return false;
    }
    /// The detail of the part named `name` ("" when there is none).
    std::string detail(const std::string& name) const {
        for (const BuildPart& p : parts)
            if (p.name == name)
                return p.detail;
        return {};
    }
};

} // namespace polycut::sim

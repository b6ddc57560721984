// Meshes of the unit box for the DG tests: hexes, prisms, tets, jittered tets, random-plane cut
// cells, a mesh with a sliver layer.
#pragma once

#include "polycut/elasticity/material.hpp"
#include "polycut/mesh/mesh.hpp"

#include <string>

namespace polycut::dg::test {

/// Kinds of test mesh.
enum class Kind { Hex, Prism, Tet, JitteredTet, Cut, Sliver, NonConvex };
std::string name(Kind k);

/// A mesh of the box [0, 1]^3 with n blocks per axis.
mesh::Mesh box_mesh(Kind kind, int n);

/// Boundary faces whose nodes all lie on the plane x = x0 (n = -1 for x0 = 0).
std::vector<Index> faces_on_plane(const mesh::Mesh& m, int axis, double value);
/// All boundary faces.
std::vector<Index> all_boundary_faces(const mesh::Mesh& m);

/// Soft tissue: E = 1e4 Pa, nu = 0.45, rho = 1000 kg/m^3.
inline elasticity::Material tissue_material() {
    elasticity::Material m;
    m.youngs_modulus = 1e4;
    m.poisson_ratio = 0.45;
    m.density = 1000;
    return m;
}

} // namespace polycut::dg::test

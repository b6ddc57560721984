#include "polycut/basis/cell_basis.hpp"

#include "polycut/basis/harmonic.hpp"
#include "polycut/basis/mean_value.hpp"
#include "polycut/basis/p1.hpp"
#include "polycut/basis/q1.hpp"
#include "polycut/common/error.hpp"

#include <stdexcept>

namespace polycut::basis {

CellIntegration integrate_cell(const mesh::Mesh& mesh, Index cell, const BasisOptions& options) {
    const mesh::Cell& c = mesh.cells.at(std::size_t(cell));
    try {
        switch (c.shape) {
        case mesh::CellShape::Tet: {
            std::array<Vec3, 4> X;
            for (std::size_t i = 0; i < 4; ++i)
                X[i] = mesh.rest[std::size_t(c.nodes.at(i))];
            return p1_integration(X);
        }
        case mesh::CellShape::Hex: {
            std::array<Vec3, 8> X;
            for (std::size_t i = 0; i < 8; ++i)
                X[i] = mesh.rest[std::size_t(c.nodes.at(i))];
            return q1_integration(X, 2);
        }
        case mesh::CellShape::Polyhedron:
            if (options.poly == PolyBasis::MeanValue) {
                if (options.rule == PolyRule::MonteCarlo)
                    throw std::logic_error("Monte Carlo integration is for harmonic cells only");
                return integrate_mean_value(mesh, cell,
                    options.rule == PolyRule::Heuristic ? MvcRule::Heuristic : MvcRule::Reference,
                    options.gauss_degree);
            } else {
                HarmonicIntegration integration;
                integration.rule = options.rule == PolyRule::MonteCarlo ? HarmonicRule::MonteCarlo
                                                                        : HarmonicRule::Gauss;
                integration.gauss_degree = options.gauss_degree;
                HarmonicOptions harmonic;
                harmonic.offset = options.harmonic_xi;
                return integrate_harmonic(mesh, cell, integration, harmonic);
            }
        }
    } catch (const MeshError& e) {
        if (e.cell() >= 0)
            throw;
        throw MeshError(cell, -1, e.problem());
    }
    throw std::logic_error("unknown cell shape");
}

} // namespace polycut::basis

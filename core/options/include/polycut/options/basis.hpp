// Options of core/basis: which polyhedral basis, which quadrature, how the volumetric strain is
// integrated. Plain data in the options layer (docs/decisions/0051), the one place their defaults
// live.
#pragma once

namespace polycut::basis {

/// Basis for cells that are neither tets nor hexes.
enum class PolyBasis { MeanValue, Harmonic };

/// Quadrature for polyhedral bases: Wicke's heuristic (vertex + face samples, 000), a reference
/// rule (centroid tetrahedralization + Gauss, 001), or Monte Carlo (001).
enum class PolyRule { Heuristic, Reference, MonteCarlo };

/// How a cell integrates the volumetric (dilatational) part of its strain energy.
enum class VolumetricRule {
    Full, ///< with the cell's quadrature, like the rest: Q1 and polyhedra lock as nu -> 0.5
    /// B-bar mean dilatation (Hughes 1980): the cell's average volumetric strain replaces the
    /// pointwise one, one pressure per cell; no volumetric locking for Q1 hexes and polyhedra.
    /// P1 tets are unchanged (their strain is constant already).
    MeanDilatation,
    /// Averaged nodal dilatation (Bonet & Burton 1998; docs/decisions/0050): cells keep their
    /// deviatoric stiffness, the volumetric strain energy is taken per node from the
    /// volume-weighted mean of the cell dilatations around it (one pressure per node). No
    /// volumetric locking for P1 tets; couples nodes two rings apart (a wider pattern).
    NodalAverage,
};

/// Options of the per-cell bases.
struct BasisOptions {
    PolyBasis poly = PolyBasis::MeanValue; ///< basis of general polyhedra
    PolyRule rule = PolyRule::Heuristic; ///< quadrature of general polyhedra
    int gauss_degree = 2; ///< degree of the tet rule inside PolyRule::Reference
    /// MFS source offset of the harmonic basis (001 eq. 12), relative to the cell size; at most
    /// HarmonicOptions::nonconvex_offset for non-convex cells.
    double harmonic_xi = 0.15;
    VolumetricRule volumetric = VolumetricRule::Full; ///< elasticity::element_stiffness
    /// Stabilisation of general polyhedra (dimensionless): each cell's stiffness gains
    /// stabilization x tr(Ke) / (3 n) x (I - P), P the least-squares projection of its n node
    /// displacements onto affine fields, as the virtual element method stabilises the modes its
    /// consistency term leaves free. Affine fields (the patch test, rigid motions) are
    /// untouched. A cell a cut left with nodes micrometres apart, or a heuristic quadrature that
    /// misses a node's neighbourhood, has deformation modes of ~1e-7 of its mean stiffness;
    /// corotation pumped energy into them until the body exploded (issue 12, the blob organ
    /// cut by cell splitting). 0 turns it off.
    double stabilization = 0.005;
};

} // namespace polycut::basis

// Options of the discontinuous Galerkin method (seed 003): the single source of their defaults,
// in the options layer (docs/decisions/0051).
#pragma once

namespace polycut::dg {

/// Numerical flux of 003 sec. 4.
enum class Flux {
    InteriorPenalty, ///< symmetric interior penalty (003 eq. 8; "ip"): consistent, converges
    BabuskaZlamal, ///< penalty only (003 eq. 6; "bz"): PD for any penalty, not consistent
};

/// Which jump the lambda part of the penalty acts on.
enum class LambdaPenalty {
    /// eta_F (lambda + 2 mu) on the whole jump [[u]] (the default)
    Full,
    /// 2 mu eta on the whole jump plus lambda eta on its normal part ([[u]].n) only (Hansbo and
    /// Larson 2002): the tangential jump is not stiffened by lambda, which removes the volumetric
    /// locking of the full penalty as nu -> 1/2.
    Normal,
};

/// DG discretisation settings.
struct DgOptions {
    int degree = 1; ///< polynomial degree p of every cell (1 or 2)
    Flux flux = Flux::InteriorPenalty;
    /// alpha of the face penalty eta_F = alpha p^2 |F| / min(|K-|, |K+|) (003 eq. 7 made
    /// scale-invariant and safe on slivers), times the material modulus of `lambda_penalty`;
    /// dimensionless, > 0. IP is coercive above a mesh-dependent threshold (tests: 10 is safe on
    /// hexes, tets, prisms, cut and sliver cells; 0.1 is not).
    double penalty = 10.0;
    /// alpha of the Nitsche penalty on Dirichlet faces (same formula, |K| the cell's volume).
    /// Larger than `penalty` because a coarse cell cannot represent the boundary layer of a
    /// clamp: with alpha = 10 a single p = 2 cell clamped on a small face (falling_cell.json)
    /// tilts 4x more than with 1000, the clamp acting as a soft spring; a large boundary alpha
    /// does not cause the penalty locking a large interior alpha does (the clamp is the exact
    /// condition). Dimensionless, > 0.
    double dirichlet_penalty = 100.0;
    LambdaPenalty lambda_penalty = LambdaPenalty::Full;
};

} // namespace polycut::dg

// Penalty contact between the tissue and rigid bodies (scene obstacles, client-driven tools),
// issue 15 item 1, 003 sec. 9 and 001 sec. 6. The tissue is sampled at material points (its
// surface nodes, or the vertices of an embedded surface, each a weighted sum of nodes) that
// carry a share of the surface area. A sample at p inside a body (signed distance phi < 0,
// outward normal n) feels
//     f = -k a phi n,   k the body's stiffness [N/m^3], a the sample's area [m^2],
// pressure proportional to penetration depth, so the response does not depend on how finely
// the surface is sampled. Its Jacobian -df/dp = k a n n^T enters the implicit system as 3x3
// blocks (003 eq. 20-21, integrate/penalty.hpp). Friction is Coulomb-like, regularized below a
// slip velocity: f_t = -mu |f| v_t / max(|v_t|, v_slip), v_t the tangential velocity of the
// sample relative to the body, taken into the system as the damping D = mu |f| / max(|v_t|,
// v_slip) (I - n n^T), which is dissipative for any mu.
#pragma once

#include "polycut/contact/shape.hpp"
#include "polycut/integrate/penalty.hpp"

#include <cstdint>
#include <map>
#include <vector>

namespace polycut::contact {

/// How a body pushes back.
struct ContactParams {
    /// Penalty stiffness: contact pressure per metre of penetration [N/m^3] (Pa/m), > 0.
    /// At 1e6 the 1.3 N organ of assets/scenes/organ_table_probe.json sinks at most 2.4 mm.
    double stiffness = 1e6;
    /// Coulomb friction coefficient mu (dimensionless), >= 0; 0 = frictionless.
    double friction = 0;
    /// Tangential speed below which friction is viscous instead of Coulomb [m/s], > 0.
    double slip_velocity = 1e-3;
};

/// A rigid body: a shape at a pose, moving with a rigid velocity (tools; obstacles hold still).
struct Body {
    Shape shape;
    Pose pose;
    ContactParams params;
    Vec3 velocity = Vec3::Zero(); ///< of pose.position [m/s]
    Vec3 angular_velocity = Vec3::Zero(); ///< about pose.position [rad/s]
};

/// What the tissue does to a body.
struct Reaction {
    Vec3 force = Vec3::Zero(); ///< total force on the body [N]
    Vec3 torque = Vec3::Zero(); ///< about the body's pose position [N m]
    int points = 0; ///< samples inside the body
    double max_depth = 0; ///< deepest penetration [m]
};

/// The tissue's contact samples: sample s is sum_k weights[k] x_{nodes[k]} over k in
/// [offsets[s], offsets[s + 1]), with surface area areas[s].
struct Samples {
    std::vector<std::uint32_t> offsets { 0 }; ///< (#S + 1)
    std::vector<Index> nodes;
    std::vector<double> weights;
    std::vector<double> areas; ///< (#S) [m^2]
    /// Optional surface triangles over the samples (#T x 3 sample indices), outward: the
    /// samples' normals in the current configuration come from them (see signed_distance's
    /// `facing`).
    std::vector<std::uint32_t> triangles;
    /// Optional connected piece of each sample (#S): with self contact on, a sample is pushed
    /// out of the surface triangles of the other pieces (those a cut separated).
    std::vector<Index> pieces;
    std::size_t size() const { return areas.size(); }
};

/// Bodies plus samples; the integrator's penalty field.
class ContactField : public integrate::PenaltyField {
public:
    /// Adds a body; returns its id (>= 1, never reused).
    long add_body(Body body);
    /// The body with this id, or nullptr.
    Body* body(long id);
    const Body* body(long id) const;
    bool remove_body(long id);
    const std::map<long, Body>& bodies() const { return m_bodies; }
    void clear_bodies() { m_bodies.clear(); }

    /// Replaces the samples (after a cut renumbered the nodes, or to switch to an embedded
    /// surface).
    void set_samples(Samples samples);
    const Samples& samples() const { return m_samples; }

    /// integrate::PenaltyField: the samples inside a body at positions x or x + h v.
    void evaluate(const MatX3& x, const MatX3& v, double h, integrate::PenaltySet& out) override;
    double energy(const MatX3& x) const override;

    /// What the tissue at positions x, velocities v does to every body (force and torque
    /// with friction), by id.
    std::map<long, Reaction> reactions(const MatX3& x, const MatX3& v) const;

    /// Contact between the pieces of the tissue (Samples::pieces) with penalty stiffness
    /// `stiffness` [N/m^3] (0: off). A sample p of one piece behind a surface triangle t of
    /// another (its projection inside t, within `thickness` [m] of its plane on the inner
    /// side, the surfaces facing each other) feels f = -k a g n, g = n . (p - sum_i b_i t_i) < 0,
    /// and t's corners feel -b_i f:
    /// one penalty point over p's and t's nodes. Blocks between nodes of different cells fall
    /// outside the elastic pattern and are dropped (the integrator counts them): the
    /// self-contact stiffness is implicit on each node's own block only.
    void set_self_contact(double stiffness, double thickness) {
        m_self_stiffness = stiffness;
        m_self_thickness = thickness;
    }
    /// Self-contact points of the last evaluate().
    int last_self_points() const { return m_last_self_points; }

    /// Wall time of the last evaluate() [ms].
    double last_evaluate_ms() const { return m_last_ms; }

private:
    /// Calls f(id, body, sample, p, distance at p, depth) for every sample inside a body at
    /// positions x or (v given, h > 0) at x + h v; depth > 0 is the larger penetration.
    template <class F> void for_each_contact(const MatX3& x, const MatX3* v, double h, F&& f) const;
    Vec3 sample_position(const MatX3& x, std::size_t s) const;
    Vec3 sample_velocity(const MatX3& v, std::size_t s) const;

    std::map<long, Body> m_bodies;
    long m_next_id = 1;
    Samples m_samples;
    mutable std::vector<Vec3> m_positions, m_predicted, m_normals; ///< of the current evaluation
    double m_last_ms = 0;
    double m_self_stiffness = 0, m_self_thickness = 0;
    mutable int m_last_self_points = 0;
    /// Self contact at positions x (m_positions filled) into `out`.
    void self_contact(integrate::PenaltySet& out) const;
};

} // namespace polycut::contact

namespace polycut::contact {

/// Samples at surface vertices that are nodes: vertex v is node vertex_nodes[v] with weight 1
/// and a third of the rest-space area of the triangles (#T x 3 indices into the vertices)
/// around it. Vertices of no triangle get no sample.
Samples node_samples(const std::vector<Vec3>& rest, const std::vector<Index>& vertex_nodes,
    const std::vector<std::uint32_t>& triangles);

} // namespace polycut::contact

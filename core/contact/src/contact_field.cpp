// Penalty contact forces, their 3x3 blocks, friction and reactions (contact_field.hpp).
#include "polycut/contact/contact_field.hpp"

#include "polycut/common/stats.hpp"

#include <cmath>

namespace polycut::contact {

namespace {
/// The force on the tissue sample and the blocks of one contact.
struct ContactForce {
    Vec3 normal_force = Vec3::Zero(); ///< -k a phi n [N]
    double k = 0; ///< k a [N/m]
    Mat3 damping = Mat3::Zero(); ///< friction [N s/m]
    Vec3 body_velocity = Vec3::Zero(); ///< of the body at the sample [m/s]
};

/// `d`: the distance at p (the linearization point); `depth` > 0: the penetration that makes
/// the contact active (at p or at the predicted position), which friction is bounded by.
ContactForce contact_force(const Body& b, double area, const Vec3& p, const SignedDistance& d,
    double depth, const Vec3* pdot) {
    ContactForce c;
    c.k = b.params.stiffness * area;
    c.normal_force = -c.k * d.phi * d.normal;
    c.body_velocity = b.velocity + b.angular_velocity.cross(p - b.pose.position);
    if (b.params.friction > 0 && pdot) {
        const Mat3 tangent = Mat3::Identity() - d.normal * d.normal.transpose();
        const Vec3 vt = tangent * (*pdot - c.body_velocity);
        const double mu_fn = b.params.friction * c.k * depth;
        c.damping = mu_fn / std::max(vt.norm(), b.params.slip_velocity) * tangent;
    }
    return c;
}
} // namespace

long ContactField::add_body(Body body) {
    const long id = m_next_id++;
    m_bodies.emplace(id, std::move(body));
    return id;
}

Body* ContactField::body(long id) {
    auto it = m_bodies.find(id);
    return it == m_bodies.end() ? nullptr : &it->second;
}

const Body* ContactField::body(long id) const {
    auto it = m_bodies.find(id);
    return it == m_bodies.end() ? nullptr : &it->second;
}

bool ContactField::remove_body(long id) {
    return m_bodies.erase(id) > 0;
}

void ContactField::set_samples(Samples samples) {
    m_samples = std::move(samples);
}

Vec3 ContactField::sample_position(const MatX3& x, std::size_t s) const {
    Vec3 p = Vec3::Zero();
    for (std::uint32_t k = m_samples.offsets[s]; k < m_samples.offsets[s + 1]; ++k)
        p += m_samples.weights[k] * x.row(m_samples.nodes[k]).transpose();
    return p;
}

Vec3 ContactField::sample_velocity(const MatX3& v, std::size_t s) const {
    return sample_position(v, s);
}

template <class F>
void ContactField::for_each_contact(const MatX3& x, const MatX3* v, double h, F&& f) const {
    const std::size_t n = m_samples.size();
    const bool predict = v && h > 0 && v->rows() == x.rows();
    m_positions.resize(n);
    m_predicted.resize(predict ? n : 0);
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::size_t s = 0; s < n; ++s) {
        m_positions[s] = sample_position(x, s);
        if (predict)
            m_predicted[s] = m_positions[s] + h * sample_position(*v, s);
        if (!m_positions[s].allFinite() || (predict && !m_predicted[s].allFinite()))
            return; // a broken state gets no contact (the integrator rolls it back)
        lo = lo.cwiseMin(m_positions[s]);
        hi = hi.cwiseMax(m_positions[s]);
        if (predict) {
            lo = lo.cwiseMin(m_predicted[s]);
            hi = hi.cwiseMax(m_predicted[s]);
        }
    }
    // Area-weighted outward normals of the samples at x (zero when no triangles are given).
    m_normals.assign(m_samples.triangles.empty() ? 0 : n, Vec3::Zero());
    for (std::size_t t = 0; t + 2 < m_samples.triangles.size(); t += 3) {
        const std::uint32_t a = m_samples.triangles[t], b = m_samples.triangles[t + 1],
                            c = m_samples.triangles[t + 2];
        const Vec3 area_normal
            = (m_positions[b] - m_positions[a]).cross(m_positions[c] - m_positions[a]);
        m_normals[a] += area_normal;
        m_normals[b] += area_normal;
        m_normals[c] += area_normal;
    }
    auto inside_box = [](const Vec3& p, const Vec3& blo, const Vec3& bhi) {
        return (p.array() >= blo.array()).all() && (p.array() <= bhi.array()).all();
    };
    for (const auto& [id, b] : m_bodies) {
        Vec3 blo, bhi;
        world_bounds(b.shape, b.pose, blo, bhi);
        if ((blo.array() > hi.array()).any() || (bhi.array() < lo.array()).any())
            continue;
        for (std::size_t s = 0; s < n; ++s) {
            const Vec3& p = m_positions[s];
            const bool now = inside_box(p, blo, bhi);
            const bool next = predict && inside_box(m_predicted[s], blo, bhi);
            if (!now && !next)
                continue;
            // The linearization point is the current position, whichever made it active.
            const Vec3* facing = m_normals.empty() ? nullptr : &m_normals[s];
            const SignedDistance d = signed_distance(b.shape, b.pose, p, facing);
            double depth = -d.phi;
            if (next) {
                const SignedDistance dp = signed_distance(b.shape, b.pose, m_predicted[s], facing);
                depth = std::max(depth, -dp.phi);
            }
            if (depth > 0)
                f(id, b, s, p, d, depth);
        }
    }
}

void ContactField::evaluate(const MatX3& x, const MatX3& v, double h, integrate::PenaltySet& out) {
    const Stopwatch watch;
    out.clear();
    const bool has_v = v.rows() == x.rows();
    for_each_contact(x, has_v ? &v : nullptr, h,
        [&](long, const Body& b, std::size_t s, const Vec3& p, const SignedDistance& d,
            double depth) {
            const Vec3 pdot = has_v ? sample_velocity(v, s) : Vec3::Zero();
            const ContactForce c
                = contact_force(b, m_samples.areas[s], p, d, depth, has_v ? &pdot : nullptr);
            integrate::PenaltyPoint point;
            point.first = std::uint32_t(out.nodes.size());
            point.count = m_samples.offsets[s + 1] - m_samples.offsets[s];
            for (std::uint32_t k = m_samples.offsets[s]; k < m_samples.offsets[s + 1]; ++k) {
                out.nodes.push_back(m_samples.nodes[k]);
                out.weights.push_back(m_samples.weights[k]);
            }
            point.force = c.normal_force;
            // The Gauss-Newton part of the Hessian of 1/2 k a phi^2: the curvature term
            // k a phi dn/dp is indefinite inside a convex body and is left out.
            point.stiffness = c.k * d.normal * d.normal.transpose();
            point.damping = c.damping;
            point.other_velocity = c.body_velocity;
            out.points.push_back(point);
        });
    m_last_ms = watch.ms();
}

double ContactField::energy(const MatX3& x) const {
    double e = 0;
    for_each_contact(x, nullptr, 0.0,
        [&](long, const Body& b, std::size_t s, const Vec3&, const SignedDistance& d, double) {
            e += 0.5 * b.params.stiffness * m_samples.areas[s] * d.phi * d.phi;
        });
    return e;
}

std::map<long, Reaction> ContactField::reactions(const MatX3& x, const MatX3& v) const {
    std::map<long, Reaction> out;
    for (const auto& [id, b] : m_bodies)
        out[id] = Reaction {};
    const bool has_v = v.rows() == x.rows();
    for_each_contact(x, nullptr, 0.0,
        [&](long id, const Body& b, std::size_t s, const Vec3& p, const SignedDistance& d,
            double depth) {
            const Vec3 pdot = has_v ? sample_velocity(v, s) : Vec3::Zero();
            const ContactForce c
                = contact_force(b, m_samples.areas[s], p, d, depth, has_v ? &pdot : nullptr);
            // The force on the tissue is the normal force plus friction -D (pdot - v_body); the
            // body feels the opposite.
            const Vec3 on_tissue = c.normal_force - c.damping * (pdot - c.body_velocity);
            Reaction& r = out[id];
            r.force -= on_tissue;
            r.torque += (p - b.pose.position).cross(-on_tissue);
            ++r.points;
            r.max_depth = std::max(r.max_depth, -d.phi);
        });
    return out;
}

} // namespace polycut::contact

namespace polycut::contact {

Samples node_samples(const std::vector<Vec3>& rest, const std::vector<Index>& vertex_nodes,
    const std::vector<std::uint32_t>& triangles) {
    std::vector<double> area(vertex_nodes.size(), 0.0);
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const Vec3& a = rest[std::size_t(vertex_nodes[triangles[t]])];
        const Vec3& b = rest[std::size_t(vertex_nodes[triangles[t + 1]])];
        const Vec3& c = rest[std::size_t(vertex_nodes[triangles[t + 2]])];
        const double third = (b - a).cross(c - a).norm() / 6.0;
        for (int k = 0; k < 3; ++k)
            area[triangles[t + std::size_t(k)]] += third;
    }
    Samples out;
    std::vector<std::uint32_t> sample_of(vertex_nodes.size(), 0);
    for (std::size_t v = 0; v < vertex_nodes.size(); ++v) {
        if (!(area[v] > 0))
            continue;
        sample_of[v] = std::uint32_t(out.areas.size());
        out.nodes.push_back(vertex_nodes[v]);
        out.weights.push_back(1.0);
        out.areas.push_back(area[v]);
        out.offsets.push_back(std::uint32_t(out.nodes.size()));
    }
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        if (!(area[triangles[t]] > 0 && area[triangles[t + 1]] > 0 && area[triangles[t + 2]] > 0))
            continue;
        for (int k = 0; k < 3; ++k)
            out.triangles.push_back(sample_of[triangles[t + std::size_t(k)]]);
    }
    return out;
}

} // namespace polycut::contact

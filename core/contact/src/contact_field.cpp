// Penalty contact forces, their 3x3 blocks, friction and reactions (contact_field.hpp).
#include "polycut/contact/contact_field.hpp"

#include "polycut/common/stats.hpp"

#include <cmath>
#include <unordered_map>

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
    m_last_self_points = 0;
    if (m_self_stiffness > 0 && !m_samples.pieces.empty() && !m_samples.triangles.empty())
        self_contact(out);
    m_last_ms = watch.ms();
}

void ContactField::self_contact(integrate::PenaltySet& out) const {
    // Triangles of every piece in a uniform hash grid (cell = thickness x 4), then each sample
    // against the triangles of other pieces near it.
    const auto& tri = m_samples.triangles;
    const std::size_t nt = tri.size() / 3;
    if (nt == 0 || m_positions.size() != m_samples.size())
        return;
    const double cell = 4 * m_self_thickness;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
    auto key = [&](const Eigen::Vector3i& c) {
        return (std::uint64_t(std::uint32_t(c.x()) & 0x1fffff) << 42)
            | (std::uint64_t(std::uint32_t(c.y()) & 0x1fffff) << 21)
            | std::uint64_t(std::uint32_t(c.z()) & 0x1fffff);
    };
    auto cell_of = [&](const Vec3& p) {
        return Eigen::Vector3i(int(std::floor(p.x() / cell)), int(std::floor(p.y() / cell)),
            int(std::floor(p.z() / cell)));
    };
    for (std::uint32_t t = 0; t < nt; ++t) {
        Vec3 lo = m_positions[tri[3 * t]], hi = lo;
        for (int k = 1; k < 3; ++k) {
            lo = lo.cwiseMin(m_positions[tri[3 * t + std::size_t(k)]]);
            hi = hi.cwiseMax(m_positions[tri[3 * t + std::size_t(k)]]);
        }
        const Eigen::Vector3i a = cell_of(lo - Vec3::Constant(m_self_thickness)),
                              b = cell_of(hi + Vec3::Constant(m_self_thickness));
        if (((b - a).array() > 64).any())
            continue; // a triangle far larger than the band: a broken state
        for (int i = a.x(); i <= b.x(); ++i)
            for (int j = a.y(); j <= b.y(); ++j)
                for (int k = a.z(); k <= b.z(); ++k)
                    grid[key({ i, j, k })].push_back(t);
    }
    for (std::size_t s = 0; s < m_samples.size(); ++s) {
        const Vec3& p = m_positions[s];
        const auto it = grid.find(key(cell_of(p)));
        if (it == grid.end())
            continue;
        double best = 0; // the deepest triangle the sample is behind
        std::uint32_t best_t = 0;
        Vec3 best_b = Vec3::Zero(), best_n = Vec3::Zero();
        for (const std::uint32_t t : it->second) {
            const std::uint32_t i0 = tri[3 * t], i1 = tri[3 * t + 1], i2 = tri[3 * t + 2];
            if (m_samples.pieces[i0] == m_samples.pieces[s])
                continue;
            const Vec3 &a = m_positions[i0], &b = m_positions[i1], &c = m_positions[i2];
            Vec3 n = (b - a).cross(c - a);
            const double twice_area = n.norm();
            if (!(twice_area > 0))
                continue;
            n /= twice_area;
            // Surfaces that face each other only: a sample on an edge shared with the other
            // piece's top (the lips of a cut start where the skin of both pieces meets) is
            // behind that top's plane without being inside the piece.
            if (!m_normals.empty() && !(m_normals[s].normalized().dot(n) < -0.3))
                continue;
            const double g = n.dot(p - a);
            if (!(g < 0 && g > -m_self_thickness) || !(g < best))
                continue;
            // Barycentric coordinates of the projection; inside the triangle only.
            const Vec3 q = p - g * n;
            const double wa = n.dot((b - q).cross(c - q)) / twice_area;
            const double wb = n.dot((c - q).cross(a - q)) / twice_area;
            const double wc = 1 - wa - wb;
            if (wa < 0 || wb < 0 || wc < 0)
                continue;
            best = g;
            best_t = t;
            best_b = Vec3(wa, wb, wc);
            best_n = n;
        }
        if (!(best < 0))
            continue;
        const double k = m_self_stiffness * m_samples.areas[s];
        integrate::PenaltyPoint point;
        point.first = std::uint32_t(out.nodes.size());
        auto add = [&](std::size_t sample, double scale) {
            for (std::uint32_t j = m_samples.offsets[sample]; j < m_samples.offsets[sample + 1];
                 ++j) {
                out.nodes.push_back(m_samples.nodes[j]);
                out.weights.push_back(scale * m_samples.weights[j]);
            }
        };
        add(s, 1.0);
        for (int c = 0; c < 3; ++c)
            add(tri[3 * best_t + std::size_t(c)], -best_b[c]);
        point.count = std::uint32_t(out.nodes.size()) - point.first;
        point.force = -k * best * best_n;
        point.stiffness = k * best_n * best_n.transpose();
        out.points.push_back(point);
        ++m_last_self_points;
    }
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

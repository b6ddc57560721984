// sim::Simulation: penalty contact with the scene's obstacles and the client's tools (issue 15
// item 1). The contact field lives here; the integrator evaluates it inside every step.
#include "impl.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/contact/contact_field.hpp"
#include "polycut/meshing/surface.hpp"

#include <cmath>
#include <filesystem>

namespace polycut::sim {

ToolPose scripted_pose(const scene::ScriptedTool& tool, double t);

namespace {
/// The scene's values over contact::ContactParams' defaults, then a body's own.
contact::ContactParams params_for(
    const scene::Contact& c, std::optional<double> stiffness, std::optional<double> friction) {
    contact::ContactParams p;
    p.stiffness = stiffness.value_or(c.stiffness.value_or(p.stiffness));
    p.friction = friction.value_or(c.friction.value_or(p.friction));
    p.slip_velocity = c.slip_velocity.value_or(p.slip_velocity);
    return p;
}

Eigen::Quaterniond axis_angle(const Vec3& rotation) {
    const double angle = rotation.norm();
    if (!(angle > 0))
        return Eigen::Quaterniond::Identity();
    return Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation / angle));
}

/// The obstacle as a shape at a pose.
contact::Body obstacle_body(const scene::Obstacle& o, const scene::Scene& s, std::size_t index) {
    using Kind = scene::Obstacle::Kind;
    contact::Body b;
    b.params = params_for(s.contact, o.stiffness, o.friction);
    b.pose.position = o.point;
    switch (o.kind) {
    case Kind::Plane:
        b.shape.kind = contact::Shape::Kind::Plane;
        b.pose.rotation = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), o.normal);
        break;
    case Kind::Box:
        b.shape.kind = contact::Shape::Kind::Box;
        b.shape.half_extents = 0.5 * o.size;
        b.pose.rotation = axis_angle(o.rotation);
        break;
    case Kind::Sphere:
        b.shape.kind = contact::Shape::Kind::Sphere;
        b.shape.radius = o.radius;
        break;
    case Kind::Capsule:
        b.shape.kind = contact::Shape::Kind::Capsule;
        b.shape.radius = o.radius;
        b.shape.half_length = 0.5 * (o.b - o.a).norm();
        b.pose.position = 0.5 * (o.a + o.b);
        if ((o.b - o.a).norm() > 0)
            b.pose.rotation = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), o.b - o.a);
        break;
    case Kind::Mesh: {
        const std::string where = "/obstacles/" + std::to_string(index) + "/path";
        const std::filesystem::path path = std::filesystem::path(s.directory) / o.path;
        meshing::SurfaceMesh surface;
        try {
            surface = meshing::read_surface(path.string(), true);
        } catch (const FileError& e) {
            throw SceneError(where, e.what());
        }
        for (Vec3& p : surface.positions)
            p *= o.scale;
        b.shape.kind = contact::Shape::Kind::TriangleMesh;
        b.shape.mesh = std::make_shared<contact::TriangleMeshDistance>(
            std::move(surface.positions), surface.triangles);
        b.pose.rotation = axis_angle(o.rotation);
        break;
    }
    }
    return b;
}

contact::Shape tool_shape(const ToolSpec& t) {
    contact::Shape shape;
    switch (t.kind) {
    case ToolSpec::Kind::Sphere:
        shape.kind = contact::Shape::Kind::Sphere;
        shape.radius = t.radius;
        break;
    case ToolSpec::Kind::Capsule:
        shape.kind = contact::Shape::Kind::Capsule;
        shape.radius = t.radius;
        shape.half_length = 0.5 * t.length;
        break;
    case ToolSpec::Kind::Blade:
        shape.kind = contact::Shape::Kind::Box;
        shape.half_extents = 0.5 * t.size;
        break;
    }
    return shape;
}

void check_pose(const ToolPose& p) {
    if (!p.position.allFinite() || !(p.position.cwiseAbs().maxCoeff() <= 1e3))
        throw InputError("position", "must be 3 finite numbers within [-1000, 1000] [m]");
    const double n = p.orientation.coeffs().norm();
    if (!std::isfinite(n) || !(n > 1e-9))
        throw InputError("orientation", "must be a non-zero quaternion [w, x, y, z]");
}

/// Angular velocity that turns `from` into `to` in time dt [rad/s].
Vec3 angular_velocity(const Eigen::Quaterniond& from, const Eigen::Quaterniond& to, double dt) {
    const Eigen::AngleAxisd delta(to * from.conjugate());
    double angle = delta.angle();
    if (angle > M_PI)
        angle -= 2 * M_PI;
    return dt > 0 ? Vec3(delta.axis() * angle / dt) : Vec3::Zero();
}
} // namespace

contact::ContactField& Simulation::Impl::ensure_contact() {
    if (!contact) {
        contact = std::make_unique<contact::ContactField>();
        contact_samples_version = 0;
    }
    integrator->set_penalty_field(contact.get());
    return *contact;
}

/// A scripted tool's pose at time t: linear in position, slerp in orientation.
ToolPose scripted_pose(const scene::ScriptedTool& tool, double t) {
    const auto& keys = tool.keys;
    auto pose_of = [](const scene::ScriptedTool::Key& k) {
        ToolPose p;
        p.position = k.position;
        p.orientation = Eigen::Quaterniond(
            k.orientation[0], k.orientation[1], k.orientation[2], k.orientation[3]);
        return p;
    };
    if (t <= keys.front().t)
        return pose_of(keys.front());
    for (std::size_t i = 1; i < keys.size(); ++i)
        if (t <= keys[i].t) {
            const double s = (t - keys[i - 1].t) / (keys[i].t - keys[i - 1].t);
            const ToolPose a = pose_of(keys[i - 1]), b = pose_of(keys[i]);
            ToolPose out;
            out.position = (1 - s) * a.position + s * b.position;
            out.orientation = a.orientation.slerp(s, b.orientation);
            return out;
        }
    return pose_of(keys.back());
}

/// Connected piece of every node (union-find over the cells' nodes); nodes of no cell get -1.
static std::vector<Index> node_pieces(const mesh::Mesh& mesh) {
    std::vector<Index> root(mesh.rest.size());
    for (std::size_t i = 0; i < root.size(); ++i)
        root[i] = Index(i);
    auto find = [&](Index i) {
        while (root[std::size_t(i)] != i)
            i = root[std::size_t(i)] = root[std::size_t(root[std::size_t(i)])];
        return i;
    };
    std::vector<std::uint8_t> used(mesh.rest.size(), 0);
    for (const auto& c : mesh.cells)
        for (const Index n : c.nodes) {
            used[std::size_t(n)] = 1;
            root[std::size_t(find(n))] = find(c.nodes.front());
        }
    std::vector<Index> out(mesh.rest.size(), kNone);
    for (std::size_t i = 0; i < out.size(); ++i)
        if (used[i])
            out[i] = find(Index(i));
    return out;
}

void Simulation::Impl::build_obstacles() {
    obstacle_bodies.clear();
    scripted_tools.clear();
    if (scene.obstacles.empty() && scene.tools.empty() && !(scene.contact.self_stiffness > 0))
        return;
    contact::ContactField& field = ensure_contact();
    for (std::size_t i = 0; i < scene.obstacles.size(); ++i)
        obstacle_bodies.push_back(field.add_body(obstacle_body(scene.obstacles[i], scene, i)));
}

void Simulation::Impl::build_scripted_tools(Simulation& owner) {
    for (const scene::ScriptedTool& t : scene.tools) {
        ToolSpec spec;
        spec.kind = t.shape == scene::ToolShape::Capsule ? ToolSpec::Kind::Capsule
            : t.shape == scene::ToolShape::Blade         ? ToolSpec::Kind::Blade
                                                         : ToolSpec::Kind::Sphere;
        spec.radius = t.radius;
        spec.length = t.length;
        spec.size = t.size;
        spec.stiffness = t.stiffness;
        spec.friction = t.friction;
        spec.pose = scripted_pose(t, 0.0);
        scripted_tools.push_back(owner.add_tool(spec));
    }
}

void Simulation::Impl::prepare_contact(double dt) {
    if (!contact)
        return;
    if (contact_samples_version != topology_version
        || (!contact->samples().nodes.empty()
            && *std::max_element(contact->samples().nodes.begin(), contact->samples().nodes.end())
                >= mesh.num_nodes())) {
        // The surface changed (a cut, or its undo): sample its vertices again (the embedded
        // surface's, when the scene has one).
        refresh_embedded();
        contact::Samples samples = embedded_current()
            ? embedded_samples()
            : contact::node_samples(mesh.rest, topology.vertex_nodes, topology.triangles);
        if (scene.contact.self_stiffness > 0) {
            // The connected piece of each sample: of its first node (the nodes of one sample
            // share a cell).
            const std::vector<Index> piece = node_pieces(mesh);
            samples.pieces.clear();
            for (std::size_t i = 0; i < samples.size(); ++i)
                samples.pieces.push_back(piece[std::size_t(samples.nodes[samples.offsets[i]])]);
            contact->set_self_contact(scene.contact.self_stiffness, 0.5 * initial_cell_size);
        }
        contact->set_samples(std::move(samples));
        contact_samples_version = topology_version;
    }
    for (std::size_t i = 0; i < scripted_tools.size(); ++i) {
        auto it = tools.find(scripted_tools[i]);
        if (it != tools.end())
            it->second.pose = scripted_pose(scene.tools[i], time + dt);
    }
    for (auto& [id, t] : tools) {
        contact::Body* b = contact->body(t.body);
        if (!b)
            continue;
        b->velocity = dt > 0 ? Vec3((t.pose.position - t.stepped.position) / dt) : Vec3::Zero();
        b->angular_velocity = angular_velocity(t.stepped.orientation, t.pose.orientation, dt);
        b->pose.position = t.pose.position;
        b->pose.rotation = t.pose.orientation;
        t.stepped = t.pose;
    }
}

void Simulation::Impl::measure_contact() {
    reactions.clear();
    if (!contact)
        return;
    const Stopwatch watch;
    const auto by_body = contact->reactions(state.x, state.v);
    auto add = [&](const char* kind, long id, const std::string& name, long body) {
        auto it = by_body.find(body);
        if (it == by_body.end())
            return;
        BodyReaction r;
        r.kind = kind;
        r.id = id;
        r.name = name;
        r.force = it->second.force;
        r.torque = it->second.torque;
        r.points = it->second.points;
        r.max_depth = it->second.max_depth;
        reactions.push_back(r);
    };
    for (const auto& [id, t] : tools)
        add("tool", id, "", t.body);
    for (std::size_t i = 0; i < obstacle_bodies.size(); ++i)
        add("obstacle", long(i), scene.obstacles[i].name, obstacle_bodies[i]);
    contact_ms = contact->last_evaluate_ms() + watch.ms();
}

long Simulation::add_tool(const ToolSpec& t) {
    check_pose(t.pose);
    auto positive = [](double x, const char* what, double lo_open) {
        if (!std::isfinite(x) || !(x > lo_open) || x > 1e3)
            throw InputError(what, "must be a finite number in (0, 1000] [m]");
    };
    if (t.kind != ToolSpec::Kind::Blade)
        positive(t.radius, "radius", 0);
    if (t.kind == ToolSpec::Kind::Capsule)
        positive(t.length + 1, "length", 1); // length >= 0
    if (t.kind == ToolSpec::Kind::Blade)
        for (int i = 0; i < 3; ++i)
            positive(t.size[i], "size", 0);
    if (t.stiffness && !(std::isfinite(*t.stiffness) && *t.stiffness > 0))
        throw InputError("stiffness", "must be a finite number > 0 [N/m^3]");
    if (t.friction && !(std::isfinite(*t.friction) && *t.friction >= 0))
        throw InputError("friction", "must be a finite number >= 0");
    Impl& s = *m_impl;
    contact::Body b;
    b.shape = tool_shape(t);
    b.params = params_for(s.scene.contact, t.stiffness, t.friction);
    Impl::Tool tool;
    tool.spec = t;
    tool.spec.pose.orientation.normalize();
    tool.pose = tool.spec.pose;
    tool.stepped = tool.pose; // a new tool does not move in its first step
    b.pose.position = tool.pose.position;
    b.pose.rotation = tool.pose.orientation;
    tool.body = s.ensure_contact().add_body(b);
    const long id = s.next_id++;
    s.tools.emplace(id, tool);
    s.static_solved = false;
    return id;
}

bool Simulation::move_tool(long id, const ToolPose& pose) {
    check_pose(pose);
    auto it = m_impl->tools.find(id);
    if (it == m_impl->tools.end())
        return false;
    it->second.pose = pose;
    it->second.pose.orientation.normalize();
    m_impl->static_solved = false;
    return true;
}

bool Simulation::remove_tool(long id) {
    auto it = m_impl->tools.find(id);
    if (it == m_impl->tools.end())
        return false;
    if (m_impl->contact)
        m_impl->contact->remove_body(it->second.body);
    m_impl->tools.erase(it);
    m_impl->static_solved = false;
    return true;
}

std::size_t Simulation::tool_count() const {
    return m_impl->tools.size();
}

std::vector<std::pair<long, ToolSpec>> Simulation::tools() const {
    std::vector<std::pair<long, ToolSpec>> out;
    for (const auto& [id, t] : m_impl->tools) {
        ToolSpec spec = t.spec;
        spec.pose = t.stepped;
        out.emplace_back(id, spec);
    }
    return out;
}

const std::vector<BodyReaction>& Simulation::contact_reactions() const {
    return m_impl->reactions;
}

double Simulation::contact_ms() const {
    return m_impl->contact_ms;
}

} // namespace polycut::sim

// Session: the client-driven rigid tools (tool_create, tool_move, tool_remove; issue 15 item
// 1) and the contact reports the stream and get_stats carry.
#include "polycut/common/error.hpp"
#include "server_session.hpp"
#include "server_session_detail.hpp"

namespace polycut::server {

namespace {
using protocol::ErrorCode;
using protocol::make_error;

Eigen::Quaterniond to_quaternion(const std::optional<protocol::Quaternion>& q) {
    if (!q) {
        return Eigen::Quaterniond::Identity();
    }
    return Eigen::Quaterniond((*q)[0], (*q)[1], (*q)[2], (*q)[3]).normalized();
}

std::array<double, 7> pose_key(const sim::ToolPose& p) {
    const auto& q = p.orientation;
    return { p.position.x(), p.position.y(), p.position.z(), q.w(), q.x(), q.y(), q.z() };
}

/// The sim's InputError names the argument; the wire pointer is /params/<it>.
protocol::RpcError invalid(const InputError& e) {
    return make_error(ErrorCode::InvalidParams, "/params/" + e.where(), e.problem());
}

std::array<double, 3> to_array(const Vec3& v) {
    return { v.x(), v.y(), v.z() };
}
} // namespace

ApplyOutcome Session::tool_create(const protocol::ToolCreateParams& p) {
    sim::ToolSpec spec;
    if (p.shape == "capsule") {
        spec.kind = sim::ToolSpec::Kind::Capsule;
    } else if (p.shape == "blade") {
        spec.kind = sim::ToolSpec::Kind::Blade;
    }
    spec.radius = p.radius.value_or(spec.radius);
    spec.length = p.length.value_or(spec.length);
    if (p.size) {
        spec.size = detail::to_vec(*p.size);
    }
    spec.pose.position = detail::to_vec(p.position);
    spec.pose.orientation = to_quaternion(p.orientation);
    spec.stiffness = p.stiffness;
    spec.friction = p.friction;
    ToolEntry entry;
    try {
        entry.sim_id = m_sim->add_tool(spec);
    } catch (const InputError& e) {
        return invalid(e);
    }
    entry.pose = pose_key(spec.pose);
    const std::uint64_t id = m_next_id++;
    m_tools.emplace(id, entry);
    return detail::done(protocol::Created { id, effect_tick() });
}

ApplyOutcome Session::tool_move(const protocol::ToolMoveParams& p) {
    auto it = m_tools.find(p.id);
    if (it == m_tools.end()) {
        return make_error(
            ErrorCode::NotFound, "/params/id", "no active tool with id " + std::to_string(p.id));
    }
    sim::ToolPose pose;
    pose.position = detail::to_vec(p.position);
    const auto& old = it->second.pose;
    pose.orientation = p.orientation ? to_quaternion(p.orientation)
                                     : Eigen::Quaterniond(old[3], old[4], old[5], old[6]);
    try {
        if (!m_sim->move_tool(it->second.sim_id, pose)) {
            return make_error(ErrorCode::NotFound, "/params/id",
                "tool " + std::to_string(p.id) + " is gone from the simulation");
        }
    } catch (const InputError& e) {
        return invalid(e);
    }
    it->second.pose = pose_key(pose);
    return detail::done(protocol::Ack { effect_tick() });
}

ApplyOutcome Session::tool_remove(const protocol::ToolRemoveParams& p) {
    auto it = m_tools.find(p.id);
    if (it == m_tools.end()) {
        return make_error(
            ErrorCode::NotFound, "/params/id", "no active tool with id " + std::to_string(p.id));
    }
    m_sim->remove_tool(it->second.sim_id);
    m_tools.erase(it);
    return detail::done(protocol::Ack { effect_tick() });
}

std::vector<protocol::ContactReport> Session::contacts() const {
    std::vector<protocol::ContactReport> out;
    if (!m_sim) {
        return out;
    }
    for (const sim::BodyReaction& r : m_sim->contact_reactions()) {
        protocol::ContactReport c;
        c.kind = r.kind;
        if (r.kind == "tool") {
            // the wire id of the sim's tool
            bool found = false;
            for (const auto& [wire, t] : m_tools) {
                if (t.sim_id == r.id) {
                    c.id = wire;
                    found = true;
                }
            }
            if (!found) {
                continue;
            }
        } else {
            c.id = static_cast<std::uint64_t>(r.id);
        }
        c.force = to_array(r.force);
        c.torque = to_array(r.torque);
        c.points = static_cast<std::uint32_t>(r.points);
        c.depth = r.max_depth;
        out.push_back(c);
    }
    return out;
}

} // namespace polycut::server

// The surface stream: surface frames and events (and the surface header shared with the
// get_surface snapshot).
#include "codec_internal.hpp"

#include <cmath>

namespace polycut::protocol {

namespace detail {

namespace {

template <class T> T unwrap(Expected<T, RpcError> value, ErrorCode code) {
    if (!value) {
        RpcError error = value.error();
        error.code = code;
        error.message = std::string(default_message(code));
        throw Failure { std::move(error) };
    }
    return std::move(value).value();
}

} // namespace

void write_surface_header(const SurfaceHeader& h, json& out) {
    out["seq"] = h.seq;
    out["tick"] = h.tick;
    out["sim_time"] = h.sim_time;
    out["topology_version"] = h.topology_version;
    out["vertex_count"] = h.vertex_count;
    out["triangle_count"] = h.triangle_count;
    out["has_topology"] = h.has_topology;
    json step = json::object();
    step["step_ms"] = h.step.step_ms;
    step["solver_iterations"] = h.step.solver_iterations;
    // A non-finite residual (a diverged solve) is sent as null: JSON has no NaN.
    step["residual"] = std::isfinite(h.step.residual) ? json(h.step.residual) : json(nullptr);
    step["warnings"] = h.step.warnings;
    out["step"] = std::move(step);
    json applied = json::array();
    for (const auto& id : h.applied) {
        applied.push_back(request_id_to_json(id));
    }
    out["applied"] = std::move(applied);
    out["cut_deferred"] = h.cut_deferred;
    if (!h.contacts.empty()) {
        out["contacts"] = contacts_json(h.contacts);
    }
}

json contacts_json(const std::vector<ContactReport>& contacts) {
    json out = json::array();
    for (const ContactReport& c : contacts) {
        out.push_back({ { "kind", c.kind }, { "id", c.id }, { "force", c.force },
            { "torque", c.torque }, { "points", c.points }, { "depth", c.depth } });
    }
    return out;
}

std::vector<ContactReport> read_contacts(
    const json& value, const std::string& pointer, ErrorCode code) {
    if (!value.is_array()) {
        fail(code, pointer, "must be an array of contact reports");
    }
    std::vector<ContactReport> out;
    for (std::size_t i = 0; i < value.size(); ++i) {
        ObjectReader c(value[i], pointer_append(pointer, i), code);
        ContactReport report;
        report.kind = read_string(c.required("kind"), c.at("kind"), 16, code);
        if (report.kind != "tool" && report.kind != "obstacle") {
            fail(code, c.at("kind"), "must be \"tool\" or \"obstacle\"");
        }
        report.id = read_uint(
            c.required("id"), c.at("id"), 0, std::numeric_limits<std::uint64_t>::max(), code);
        report.force = read_vector3(c.required("force"), c.at("force"), 1e300, code);
        report.torque = read_vector3(c.required("torque"), c.at("torque"), 1e300, code);
        report.points = static_cast<std::uint32_t>(read_uint(c.required("points"), c.at("points"),
            0, std::numeric_limits<std::uint32_t>::max(), code));
        report.depth = read_number(c.required("depth"), c.at("depth"), Range { 0.0 }, code);
        c.finish();
        out.push_back(report);
    }
    return out;
}

void write_surface_arrays(const SurfaceHeader& header, std::span<const float> positions,
    std::span<const std::uint32_t> triangles, std::span<const std::uint8_t> tags, json& out,
    Message& frames) {
    frames.push_back(encode_array(positions));
    out["positions"] = frame_ref_json(
        static_cast<std::uint32_t>(frames.size()), DType::Float32, { positions.size() / 3, 3 });
    if (header.has_topology) {
        frames.push_back(encode_array(triangles));
        out["triangles"] = frame_ref_json(
            static_cast<std::uint32_t>(frames.size()), DType::UInt32, { triangles.size() / 3, 3 });
        frames.push_back(encode_array(tags));
        out["tags"] = frame_ref_json(
            static_cast<std::uint32_t>(frames.size()), DType::UInt8, { tags.size() });
    }
}

SurfaceFrame read_surface(
    const json& value, const std::string& pointer, FrameSet& frames, ErrorCode code) {
    ObjectReader r(value, pointer, code);
    SurfaceFrame out;
    SurfaceHeader& h = out.header;
    constexpr std::uint64_t kU64 = std::numeric_limits<std::uint64_t>::max();
    constexpr std::uint32_t kU32 = std::numeric_limits<std::uint32_t>::max();
    h.seq = read_uint(r.required("seq"), r.at("seq"), 0, kU64, code);
    h.tick = read_int(
        r.required("tick"), r.at("tick"), 0, std::numeric_limits<std::int64_t>::max(), code);
    h.sim_time = read_number(r.required("sim_time"), r.at("sim_time"), Range {}, code);
    h.topology_version
        = read_uint(r.required("topology_version"), r.at("topology_version"), 0, kU64, code);
    h.vertex_count = static_cast<std::uint32_t>(
        read_uint(r.required("vertex_count"), r.at("vertex_count"), 0, kU32, code));
    h.triangle_count = static_cast<std::uint32_t>(
        read_uint(r.required("triangle_count"), r.at("triangle_count"), 0, kU32, code));
    h.has_topology = read_bool(r.required("has_topology"), r.at("has_topology"), code);
    {
        ObjectReader s(r.required("step"), r.at("step"), code);
        h.step.step_ms = read_number(s.required("step_ms"), s.at("step_ms"), Range { 0.0 }, code);
        h.step.solver_iterations = static_cast<std::uint32_t>(
            read_uint(s.required("solver_iterations"), s.at("solver_iterations"), 0, kU32, code));
        const json& residual = s.required("residual");
        h.step.residual = residual.is_null()
            ? std::nan("")
            : read_number(residual, s.at("residual"), Range {}, code);
        const json& warnings = s.required("warnings");
        if (!warnings.is_array()) {
            fail(code, s.at("warnings"), "must be an array of strings");
        }
        for (std::size_t i = 0; i < warnings.size(); ++i) {
            h.step.warnings.push_back(
                read_string(warnings[i], pointer_append(s.at("warnings"), i), 4096, code));
        }
    }
    const json& applied = r.required("applied");
    if (!applied.is_array()) {
        fail(code, r.at("applied"), "must be an array of request ids");
    }
    for (std::size_t i = 0; i < applied.size(); ++i) {
        h.applied.push_back(read_request_id(applied[i], pointer_append(r.at("applied"), i), code));
    }
    if (const json* deferred = r.optional("cut_deferred")) {
        h.cut_deferred
            = static_cast<std::uint32_t>(read_uint(*deferred, r.at("cut_deferred"), 0, kU32, code));
    }
    if (const json* contacts = r.optional("contacts")) {
        h.contacts = read_contacts(*contacts, r.at("contacts"), code);
    }

    const auto positions_ref = frames.read_ref(r.required("positions"), r.at("positions"), code);
    if (positions_ref.shape != std::vector<std::uint64_t> { h.vertex_count, 3 }) {
        fail(code, pointer_append(r.at("positions"), "shape"), "must be [vertex_count, 3]");
    }
    out.positions = unwrap(
        decode_float32(frames.bytes(positions_ref), positions_ref, r.at("positions")), code);
    const json* triangles = r.optional("triangles");
    const json* tags = r.optional("tags");
    if (h.has_topology) {
        if (triangles == nullptr || tags == nullptr) {
            fail(code, r.at(triangles == nullptr ? "triangles" : "tags"),
                "required when has_topology is true");
        }
        const auto tri_ref = frames.read_ref(*triangles, r.at("triangles"), code);
        if (tri_ref.shape != std::vector<std::uint64_t> { h.triangle_count, 3 }) {
            fail(code, pointer_append(r.at("triangles"), "shape"), "must be [triangle_count, 3]");
        }
        out.triangles
            = unwrap(decode_uint32(frames.bytes(tri_ref), tri_ref, r.at("triangles")), code);
        for (std::size_t i = 0; i < out.triangles.size(); ++i) {
            if (out.triangles[i] >= h.vertex_count) {
                fail(code, pointer_append(pointer_append(r.at("triangles"), i / 3), i % 3),
                    "vertex index " + std::to_string(out.triangles[i]) + " >= vertex_count "
                        + std::to_string(h.vertex_count));
            }
        }
        const auto tag_ref = frames.read_ref(*tags, r.at("tags"), code);
        if (tag_ref.shape != std::vector<std::uint64_t> { h.triangle_count }) {
            fail(code, pointer_append(r.at("tags"), "shape"), "must be [triangle_count]");
        }
        out.tags = unwrap(decode_uint8(frames.bytes(tag_ref), tag_ref, r.at("tags")), code);
        for (std::size_t i = 0; i < out.tags.size(); ++i) {
            if (out.tags[i] != static_cast<std::uint8_t>(SurfaceTag::Skin)
                && out.tags[i] != static_cast<std::uint8_t>(SurfaceTag::Cut)) {
                fail(code, pointer_append(r.at("tags"), i),
                    "tag must be 1 (skin) or 2 (cut), got " + std::to_string(out.tags[i]));
            }
        }
    } else if (triangles != nullptr || tags != nullptr) {
        fail(code, r.at(triangles != nullptr ? "triangles" : "tags"),
            "must be absent when has_topology is false");
    }
    return out;
}

} // namespace detail

using detail::json;

Message encode_surface(const SurfaceHeader& header, std::span<const float> positions,
    std::span<const std::uint32_t> triangles, std::span<const std::uint8_t> tags) {
    SurfaceHeader h = header;
    h.vertex_count = static_cast<std::uint32_t>(positions.size() / 3);
    if (h.has_topology) {
        h.triangle_count = static_cast<std::uint32_t>(triangles.size() / 3);
    }
    json root = json::object();
    detail::write_surface_header(h, root);
    Message binary;
    detail::write_surface_arrays(h, positions, triangles, tags, root, binary);
    Message message;
    message.reserve(2 + binary.size());
    message.emplace_back(kSurfaceTopic);
    message.push_back(detail::dump(root));
    for (auto& frame : binary) {
        message.push_back(std::move(frame));
    }
    return message;
}

Message encode_event(const Event& event) {
    json root = json::object();
    root["kind"] = event.kind;
    root["tick"] = event.tick;
    root["seq"] = event.seq;
    if (event.event_seq != 0) {
        root["event_seq"] = event.event_seq;
    }
    json detail_value = json::parse(event.detail_json, nullptr, false);
    root["detail"] = detail_value.is_object() ? std::move(detail_value) : json::object();
    return Message { Frame(kEventTopic), detail::dump(root) };
}

namespace {

StreamMessage decode_stream_impl(std::span<const std::string_view> frames) {
    constexpr ErrorCode kCode = ErrorCode::InvalidRequest;
    if (frames.size() < 2) {
        detail::fail(kCode, "", "a stream message has a topic frame and a JSON frame");
    }
    const json root = detail::parse_frame(frames[1]);
    detail::FrameSet binary(frames.subspan(2));
    if (frames[0] == kSurfaceTopic) {
        SurfaceFrame frame = detail::read_surface(root, "", binary, kCode);
        binary.check_all_used();
        return frame;
    }
    if (frames[0] == kEventTopic) {
        detail::ObjectReader r(root, "", kCode);
        Event event;
        event.kind = detail::read_string(r.required("kind"), r.at("kind"), 64, kCode);
        event.tick = detail::read_int(
            r.required("tick"), r.at("tick"), 0, std::numeric_limits<std::int64_t>::max(), kCode);
        if (const json* seq = r.optional("seq")) {
            event.seq = detail::read_uint(
                *seq, r.at("seq"), 0, std::numeric_limits<std::uint64_t>::max(), kCode);
        }
        if (const json* v = r.optional("event_seq")) {
            event.event_seq = detail::read_uint(
                *v, r.at("event_seq"), 0, std::numeric_limits<std::uint64_t>::max(), kCode);
        }
        const json& detail_value = r.required("detail");
        if (!detail_value.is_object()) {
            detail::fail(kCode, r.at("detail"), "must be an object");
        }
        event.detail_json = detail::dump(detail_value);
        binary.check_all_used();
        return event;
    }
    detail::fail(kCode, "", "unknown topic \"" + std::string(frames[0].substr(0, 64)) + "\"");
}

} // namespace

Expected<StreamMessage, RpcError> decode_stream(std::span<const std::string_view> frames) {
    try {
        return decode_stream_impl(frames);
    } catch (const detail::Failure& failure) {
        return failure.error;
    } catch (const std::exception& e) {
        return make_error(ErrorCode::InternalError, "", std::string("decoder: ") + e.what());
    }
}

Expected<StreamMessage, RpcError> decode_stream(const Message& message) {
    const auto views = frame_views(message);
    return decode_stream(std::span<const std::string_view>(views));
}

} // namespace polycut::protocol

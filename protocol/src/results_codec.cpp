// Results of every method <-> JSON. Readers of results ignore unknown members, so a server may
// add result members within polycut/1 without breaking clients.
#include "codec_internal.hpp"

namespace polycut::protocol {

std::size_t result_index(Method method) {
    switch (method) {
    case Method::Hello:
        return 0;
    case Method::LoadScene:
        return 1;
    case Method::Reset:
    case Method::Pause:
    case Method::Resume:
    case Method::Step:
    case Method::SetRate:
        return 2;
    case Method::RemoveForce:
    case Method::MoveGrab:
    case Method::Release:
    case Method::Shutdown:
    case Method::ToolMove:
    case Method::ToolRemove:
        return 3;
    case Method::ApplyForce:
    case Method::Grab:
    case Method::ToolCreate:
        return 4;
    case Method::Cut:
    case Method::EndStroke:
        return 5;
    case Method::Scalpel:
        return 6;
    case Method::GetSurface:
        return 7;
    case Method::GetStats:
        return 8;
    }
    return 3;
}

namespace detail {

namespace {

constexpr ErrorCode kCode = ErrorCode::InvalidRequest;
constexpr std::uint64_t kU64 = std::numeric_limits<std::uint64_t>::max();
constexpr std::uint32_t kU32 = std::numeric_limits<std::uint32_t>::max();
constexpr std::int64_t kI64 = std::numeric_limits<std::int64_t>::max();

/// Typed member readers for result objects.
struct Members {
    ObjectReader r;
    std::uint64_t u64(std::string_view key) {
        return read_uint(r.required(key), r.at(key), 0, kU64, kCode);
    }
    std::uint32_t u32(std::string_view key) {
        return static_cast<std::uint32_t>(read_uint(r.required(key), r.at(key), 0, kU32, kCode));
    }
    std::int64_t tick() { return read_int(r.required("tick"), r.at("tick"), 0, kI64, kCode); }
    double number(std::string_view key) {
        return read_number(r.required(key), r.at(key), Range {}, kCode);
    }
    bool boolean(std::string_view key) { return read_bool(r.required(key), r.at(key), kCode); }
    std::string text(std::string_view key) {
        return read_string(r.required(key), r.at(key), 4096, kCode);
    }
};

json limits_json(const Limits& l) {
    return json { { "max_frame_bytes", l.max_frame_bytes },
        { "max_frames_per_message", l.max_frames_per_message },
        { "max_triangles_per_cut", l.max_triangles_per_cut },
        { "cut_triangles_per_tick", l.cut_triangles_per_tick },
        { "max_message_rate", l.max_message_rate }, { "max_step_ticks", l.max_step_ticks },
        { "max_rate_hz", l.max_rate_hz }, { "max_json_bytes", l.max_json_bytes },
        { "json_bytes_per_tick", l.json_bytes_per_tick }, { "max_in_flight", l.max_in_flight },
        { "max_scene_bytes", l.max_scene_bytes } };
}

Limits read_limits(const json& value, const std::string& pointer) {
    Members m { ObjectReader(value, pointer, kCode) };
    Limits l;
    l.max_frame_bytes = m.u64("max_frame_bytes");
    l.max_frames_per_message = m.u32("max_frames_per_message");
    l.max_triangles_per_cut = m.u32("max_triangles_per_cut");
    l.max_message_rate = m.number("max_message_rate");
    l.max_step_ticks = m.u32("max_step_ticks");
    l.max_rate_hz = m.number("max_rate_hz");
    // Optional: absent from older servers.
    if (const json* v = m.r.optional("max_json_bytes"); v != nullptr) {
        l.max_json_bytes = read_uint(*v, m.r.at("max_json_bytes"), 0, kU64, kCode);
    }
    if (const json* v = m.r.optional("json_bytes_per_tick"); v != nullptr) {
        l.json_bytes_per_tick = read_uint(*v, m.r.at("json_bytes_per_tick"), 0, kU64, kCode);
    }
    if (const json* v = m.r.optional("max_in_flight"); v != nullptr) {
        l.max_in_flight
            = static_cast<std::uint32_t>(read_uint(*v, m.r.at("max_in_flight"), 0, kU32, kCode));
    }
    if (const json* v = m.r.optional("cut_triangles_per_tick"); v != nullptr) {
        l.cut_triangles_per_tick = static_cast<std::uint32_t>(
            read_uint(*v, m.r.at("cut_triangles_per_tick"), 0, kU32, kCode));
    }
    if (const json* v = m.r.optional("max_scene_bytes"); v != nullptr) {
        l.max_scene_bytes = read_uint(*v, m.r.at("max_scene_bytes"), 0, kU64, kCode);
    }
    return l;
}

} // namespace

Result decode_result(Method method, const json& value, FrameSet& frames) {
    const std::string pointer = "/result";
    if (method == Method::GetSurface) {
        SurfaceFrame snapshot = read_surface(value, pointer, frames, kCode);
        if (!snapshot.header.has_topology) {
            fail(kCode, pointer + "/has_topology", "a snapshot always carries its topology");
        }
        return snapshot;
    }
    Members m { ObjectReader(value, pointer, kCode) };
    switch (result_index(method)) {
    case 0: {
        HelloResult h;
        h.protocol = m.text("protocol");
        h.server = m.text("server");
        h.limits = read_limits(m.r.required("limits"), m.r.at("limits"));
        const json& caps = m.r.required("capabilities");
        if (!caps.is_array()) {
            fail(kCode, m.r.at("capabilities"), "must be an array of strings");
        }
        for (std::size_t i = 0; i < caps.size(); ++i) {
            h.capabilities.push_back(
                read_string(caps[i], pointer_append(m.r.at("capabilities"), i), 256, kCode));
        }
        h.stream = m.text("stream");
        h.tick = m.tick();
        h.rate_hz = m.number("rate_hz");
        h.running = m.boolean("running");
        if (const json* scene = m.r.optional("scene"); scene != nullptr && !scene->is_null()) {
            h.scene = read_string(*scene, m.r.at("scene"), 4096, kCode);
        }
        return h;
    }
    case 1: {
        SceneResult sr;
        sr.tick = m.tick();
        sr.name = m.text("name");
        sr.topology_version = m.u64("topology_version");
        sr.vertex_count = m.u32("vertex_count");
        sr.triangle_count = m.u32("triangle_count");
        sr.cell_count = m.u32("cell_count");
        if (const json* v = m.r.optional("replaced_tick"); v != nullptr) {
            sr.replaced_tick = read_int(*v, m.r.at("replaced_tick"), 0, kI64, kCode);
        }
        if (m.r.optional("build_ms") != nullptr) {
            sr.build_ms = m.number("build_ms");
        }
        if (const json* parts = m.r.optional("build_parts"); parts != nullptr) {
            const std::string at = m.r.at("build_parts");
            if (!parts->is_array() || parts->size() > 64) {
                fail(kCode, at, "must be an array of at most 64 {name, ms, rss_kb} objects");
            }
            for (std::size_t i = 0; i < parts->size(); ++i) {
                Members p { ObjectReader((*parts)[i], at + "/" + std::to_string(i), kCode) };
                SceneResult::BuildPart part;
                part.name = read_string(p.r.required("name"), p.r.at("name"), 64, kCode);
                part.ms = read_number(p.r.required("ms"), p.r.at("ms"), Range { 0.0 }, kCode);
                part.rss_kb = read_int(p.r.required("rss_kb"), p.r.at("rss_kb"), 0, kI64, kCode);
                p.r.finish();
                sr.build_parts.push_back(std::move(part));
            }
        }
        return sr;
    }
    case 2:
        return RunState { m.tick(), m.boolean("running"), m.number("rate_hz") };
    case 3:
        return Ack { m.tick() };
    case 4: {
        Created c;
        c.id = read_uint(m.r.required("id"), m.r.at("id"), 1, kMaxSafeInteger, kCode);
        c.tick = m.tick();
        return c;
    }
    case 5:
        return CutResult { m.tick(), m.u64("topology_version"), m.u32("triangles"),
            m.r.optional("deferred") ? m.u32("deferred") : 0 };
    case 6:
        return ScalpelResult { m.tick(), m.u32("triangles") };
    default: {
        Stats s;
        s.tick = m.tick();
        s.sim_time = m.number("sim_time");
        s.running = m.boolean("running");
        s.rate_hz = m.number("rate_hz");
        s.seq = m.u64("seq");
        s.topology_version = m.u64("topology_version");
        s.vertex_count = m.u32("vertex_count");
        s.triangle_count = m.u32("triangle_count");
        s.cell_count = m.u32("cell_count");
        s.ticks_over_budget = m.u64("ticks_over_budget");
        s.worst_tick_ms = m.number("worst_tick_ms");
        s.step_ms_p50 = m.number("step_ms_p50");
        s.step_ms_p99 = m.number("step_ms_p99");
        s.requests = m.u64("requests");
        s.errors = m.u64("errors");
        s.clients = m.u32("clients");
        s.forces = m.u32("forces");
        s.grabs = m.u32("grabs");
        if (const json* v = m.r.optional("state_hash"); v != nullptr) {
            s.state_hash = read_string(*v, m.r.at("state_hash"), 64, kCode);
        }
        if (const json* v = m.r.optional("stream_dropped"); v != nullptr) {
            s.stream_dropped = read_uint(*v, m.r.at("stream_dropped"), 0, kU64, kCode);
        }
        if (const json* v = m.r.optional("open_strokes"); v != nullptr) {
            s.open_strokes
                = static_cast<std::uint32_t>(read_uint(*v, m.r.at("open_strokes"), 0, kU32, kCode));
        }
        if (const json* v = m.r.optional("cached_replies"); v != nullptr) {
            s.cached_replies = static_cast<std::uint32_t>(
                read_uint(*v, m.r.at("cached_replies"), 0, kU32, kCode));
        }
        if (const json* v = m.r.optional("client_states"); v != nullptr) {
            s.client_states = static_cast<std::uint32_t>(
                read_uint(*v, m.r.at("client_states"), 0, kU32, kCode));
        }
        for (auto [name, field] : { std::pair { "replies_dropped", &s.replies_dropped },
                 std::pair { "events_coalesced", &s.events_coalesced },
                 std::pair { "events_suppressed", &s.events_suppressed },
                 std::pair { "busy", &s.busy } }) {
            if (const json* v = m.r.optional(name); v != nullptr) {
                *field = read_uint(*v, m.r.at(name), 0, kU64, kCode);
            }
        }
        if (const json* v = m.r.optional("tools"); v != nullptr) {
            s.tools = static_cast<std::uint32_t>(read_uint(*v, m.r.at("tools"), 0, kU32, kCode));
        }
        if (const json* v = m.r.optional("contacts"); v != nullptr) {
            s.contacts = read_contacts(*v, m.r.at("contacts"), kCode);
        }
        for (auto [name, field] :
            { std::pair { "cut_area", &s.cut_area }, std::pair { "swept_area", &s.swept_area },
                std::pair { "swept_area_undone", &s.swept_area_undone },
                std::pair { "cut_completeness", &s.cut_completeness } }) {
            if (const json* v = m.r.optional(name); v != nullptr) {
                *field = read_number(*v, m.r.at(name), Range { 0.0 }, kCode);
            }
        }
        if (const json* v = m.r.optional("contact_ms"); v != nullptr) {
            s.contact_ms = read_number(*v, m.r.at("contact_ms"), Range { 0.0 }, kCode);
        }
        return s;
    }
    }
}

json encode_result_json(const Result& result, Message& frames) {
    json out = json::object();
    std::visit(
        [&](const auto& r) {
            using T = std::decay_t<decltype(r)>;
            if constexpr (std::is_same_v<T, HelloResult>) {
                out["protocol"] = r.protocol;
                out["server"] = r.server;
                out["limits"] = limits_json(r.limits);
                out["capabilities"] = r.capabilities;
                out["stream"] = r.stream;
                out["tick"] = r.tick;
                out["rate_hz"] = r.rate_hz;
                out["running"] = r.running;
                if (r.scene) {
                    out["scene"] = *r.scene;
                }
            } else if constexpr (std::is_same_v<T, SceneResult>) {
                out = json { { "tick", r.tick }, { "name", r.name },
                    { "topology_version", r.topology_version }, { "vertex_count", r.vertex_count },
                    { "triangle_count", r.triangle_count }, { "cell_count", r.cell_count },
                    { "build_ms", r.build_ms } };
                if (!r.build_parts.empty()) {
                    json parts = json::array();
                    for (const auto& p : r.build_parts) {
                        parts.push_back(
                            { { "name", p.name }, { "ms", p.ms }, { "rss_kb", p.rss_kb } });
                    }
                    out["build_parts"] = parts;
                }
                if (r.replaced_tick) {
                    out["replaced_tick"] = *r.replaced_tick;
                }
            } else if constexpr (std::is_same_v<T, RunState>) {
                out = json { { "tick", r.tick }, { "running", r.running },
                    { "rate_hz", r.rate_hz } };
            } else if constexpr (std::is_same_v<T, Ack>) {
                out["tick"] = r.tick;
            } else if constexpr (std::is_same_v<T, Created>) {
                out = json { { "id", r.id }, { "tick", r.tick } };
            } else if constexpr (std::is_same_v<T, CutResult>) {
                out = json { { "tick", r.tick }, { "topology_version", r.topology_version },
                    { "triangles", r.triangles }, { "deferred", r.deferred } };
            } else if constexpr (std::is_same_v<T, ScalpelResult>) {
                out = json { { "tick", r.tick }, { "triangles", r.triangles } };
            } else if constexpr (std::is_same_v<T, SurfaceSnapshot>) {
                SurfaceHeader h = r.header;
                h.has_topology = true;
                h.vertex_count = static_cast<std::uint32_t>(r.positions.size() / 3);
                h.triangle_count = static_cast<std::uint32_t>(r.triangles.size() / 3);
                write_surface_header(h, out);
                write_surface_arrays(h, r.positions, r.triangles, r.tags, out, frames);
            } else if constexpr (std::is_same_v<T, Stats>) {
                out = json { { "tick", r.tick }, { "sim_time", r.sim_time },
                    { "running", r.running }, { "rate_hz", r.rate_hz }, { "seq", r.seq },
                    { "topology_version", r.topology_version }, { "vertex_count", r.vertex_count },
                    { "triangle_count", r.triangle_count }, { "cell_count", r.cell_count },
                    { "ticks_over_budget", r.ticks_over_budget },
                    { "worst_tick_ms", r.worst_tick_ms }, { "step_ms_p50", r.step_ms_p50 },
                    { "step_ms_p99", r.step_ms_p99 }, { "requests", r.requests },
                    { "errors", r.errors }, { "clients", r.clients }, { "forces", r.forces },
                    { "grabs", r.grabs } };
                if (!r.state_hash.empty()) {
                    out["state_hash"] = r.state_hash;
                }
                out["stream_dropped"] = r.stream_dropped;
                out["open_strokes"] = r.open_strokes;
                out["cached_replies"] = r.cached_replies;
                out["client_states"] = r.client_states;
                out["replies_dropped"] = r.replies_dropped;
                out["events_coalesced"] = r.events_coalesced;
                out["events_suppressed"] = r.events_suppressed;
                out["busy"] = r.busy;
                out["tools"] = r.tools;
                out["contacts"] = contacts_json(r.contacts);
                out["contact_ms"] = r.contact_ms;
                out["cut_area"] = r.cut_area;
                out["swept_area"] = r.swept_area;
                out["swept_area_undone"] = r.swept_area_undone;
                out["cut_completeness"] = r.cut_completeness;
            }
        },
        result);
    return out;
}

} // namespace detail

} // namespace polycut::protocol

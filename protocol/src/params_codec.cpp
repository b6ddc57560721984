// Params of every method <-> JSON, with the validation rules of params.hpp.
#include "codec_internal.hpp"
#include "polycut/protocol/sweep.hpp"

namespace polycut::protocol::detail {

namespace {

constexpr ErrorCode kBad = ErrorCode::InvalidParams;
const std::string kParams = "/params";

bool valid_scene_name(const std::string& name) {
    if (name.empty() || name.size() > 64) {
        return false;
    }
    for (char c : name) {
        const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9')
            || c == '_' || c == '-';
        if (!ok) {
            return false;
        }
    }
    return true;
}

std::uint64_t read_object_id(ObjectReader& r, std::string_view key) {
    return read_uint(r.required(key), r.at(key), 1, kMaxSafeInteger);
}

std::uint64_t read_stroke(ObjectReader& r) {
    return read_uint(r.required("stroke"), r.at("stroke"), 0, kMaxSafeInteger);
}

Vector3 read_point(ObjectReader& r, std::string_view key) {
    return read_vector3(r.required(key), r.at(key), kMaxCoordinate);
}

std::vector<Triangle3> read_triangles(ObjectReader& r, FrameSet& frames, const Limits& limits) {
    const std::string pointer = r.at("triangles");
    const json& value = r.required("triangles");
    std::vector<Triangle3> triangles;
    const auto check_count = [&](std::uint64_t count) {
        if (count == 0) {
            fail(kBad, pointer, "must hold at least one triangle");
        }
        if (count > limits.max_triangles_per_cut) {
            fail(ErrorCode::PayloadTooLarge, pointer,
                std::to_string(count) + " triangles; the limit is "
                    + std::to_string(limits.max_triangles_per_cut) + " per cut");
        }
    };
    if (FrameSet::is_ref(value)) {
        const FrameRef ref = frames.read_ref(value, pointer, kBad);
        if (ref.shape.size() != 3 || ref.shape[1] != 3 || ref.shape[2] != 3) {
            fail(kBad, pointer_append(pointer, "shape"), "must be [T, 3, 3]");
        }
        check_count(ref.shape[0]);
        auto values = decode_float32(frames.bytes(ref), ref, pointer);
        if (!values) {
            throw Failure { values.error() };
        }
        triangles.resize(ref.shape[0]);
        const auto& flat = values.value();
        for (std::size_t t = 0; t < triangles.size(); ++t) {
            for (std::size_t c = 0; c < 3; ++c) {
                for (std::size_t k = 0; k < 3; ++k) {
                    const double x = flat[9 * t + 3 * c + k];
                    if (!(std::abs(x) <= kMaxCoordinate)) {
                        fail(kBad, pointer_append(pointer_append(pointer_append(pointer, t), c), k),
                            "must be >= -" + format_number(kMaxCoordinate) + " and <= "
                                + format_number(kMaxCoordinate) + ", got " + format_number(x));
                    }
                    triangles[t][c][k] = x;
                }
            }
        }
    } else {
        if (!value.is_array()) {
            fail(kBad, pointer,
                "must be an array of triangles [[x,y,z],[x,y,z],[x,y,z]] or a float32 frame "
                "reference, got "
                    + std::string(json_type_name(value)));
        }
        check_count(value.size());
        triangles.resize(value.size());
        for (std::size_t t = 0; t < value.size(); ++t) {
            const auto tri_pointer = pointer_append(pointer, t);
            const json& tri = value[t];
            if (!tri.is_array() || tri.size() != 3) {
                fail(kBad, tri_pointer, "must be an array of 3 points");
            }
            for (std::size_t c = 0; c < 3; ++c) {
                triangles[t][c]
                    = read_vector3(tri[c], pointer_append(tri_pointer, c), kMaxCoordinate);
            }
        }
    }
    return triangles;
}

std::optional<Quaternion> read_orientation(ObjectReader& r) {
    const json* v = r.optional("orientation");
    if (v == nullptr) {
        return std::nullopt;
    }
    const std::string pointer = r.at("orientation");
    if (!v->is_array() || v->size() != 4) {
        fail(kBad, pointer, "must be a quaternion [w, x, y, z] of 4 numbers");
    }
    Quaternion q {};
    double norm2 = 0;
    for (std::size_t k = 0; k < 4; ++k) {
        q[k] = read_number((*v)[k], pointer_append(pointer, k), Range { -1e3, 1e3 });
        norm2 += q[k] * q[k];
    }
    if (!(norm2 > 1e-18)) {
        fail(kBad, pointer, "must not be the zero quaternion");
    }
    return q;
}

ToolCreateParams read_tool_create(ObjectReader& r) {
    ToolCreateParams p;
    p.shape = read_string(r.required("shape"), r.at("shape"), 16);
    const Range length { 0.0, kMaxRadius, true };
    if (p.shape == "sphere" || p.shape == "capsule") {
        p.radius = read_number(r.required("radius"), r.at("radius"), length);
    }
    if (p.shape == "capsule") {
        p.length = read_number(r.required("length"), r.at("length"), Range { 0.0, kMaxRadius });
    }
    if (p.shape == "blade") {
        p.size = read_vector3(r.required("size"), r.at("size"), kMaxRadius);
        for (std::size_t k = 0; k < 3; ++k) {
            if (!((*p.size)[k] > 0)) {
                fail(kBad, pointer_append(r.at("size"), k), "must be > 0 [m]");
            }
        }
    }
    if (p.shape != "sphere" && p.shape != "capsule" && p.shape != "blade") {
        fail(kBad, r.at("shape"),
            "must be \"sphere\", \"capsule\" or \"blade\", got \"" + p.shape + "\"");
    }
    p.position = read_point(r, "position");
    p.orientation = read_orientation(r);
    if (const json* v = r.optional("stiffness")) {
        p.stiffness = read_number(*v, r.at("stiffness"), Range { 0.0, kMaxContactStiffness, true });
    }
    if (const json* v = r.optional("friction")) {
        p.friction = read_number(*v, r.at("friction"), Range { 0.0, kMaxFriction });
    }
    return p;
}

Params decode_object(Method method, ObjectReader& r, FrameSet& frames, const Limits& limits) {
    switch (method) {
    case Method::Hello: {
        HelloParams p;
        if (const json* v = r.optional("client")) {
            p.client = read_string(*v, r.at("client"), 256);
        }
        if (const json* v = r.optional("protocol")) {
            p.protocol = read_string(*v, r.at("protocol"), 64);
            if (*p.protocol != kProtocolName) {
                fail(kBad, r.at("protocol"),
                    "unsupported protocol \"" + *p.protocol + "\"; this server speaks "
                        + std::string(kProtocolName));
            }
        }
        return p;
    }
    case Method::LoadScene: {
        LoadSceneParams p;
        const json* name = r.optional("name");
        const json* scene = r.optional("scene");
        if ((name == nullptr) == (scene == nullptr)) {
            fail(kBad, kParams, "give exactly one of \"name\" or \"scene\"");
        }
        if (name != nullptr) {
            p.name = read_string(*name, r.at("name"), 64);
            if (!valid_scene_name(*p.name)) {
                fail(kBad, r.at("name"),
                    "must match [A-Za-z0-9_-]{1,64}: a scene name, never a path");
            }
        } else {
            if (!scene->is_object()) {
                fail(kBad, r.at("scene"),
                    "must be an object (an inline scene), got "
                        + std::string(json_type_name(*scene)));
            }
            p.scene_json = dump(*scene);
        }
        return p;
    }
    case Method::Reset:
        return ResetParams {};
    case Method::Pause:
        return PauseParams {};
    case Method::Resume:
        return ResumeParams {};
    case Method::Step: {
        StepParams p;
        if (const json* v = r.optional("ticks")) {
            p.ticks = static_cast<std::uint32_t>(
                read_uint(*v, r.at("ticks"), 1, limits.max_step_ticks));
        }
        return p;
    }
    case Method::SetRate:
        return SetRateParams { read_number(
            r.required("hz"), r.at("hz"), Range { 0.0, limits.max_rate_hz, true, false }) };
    case Method::ApplyForce: {
        ApplyForceParams p;
        p.point = read_point(r, "point");
        p.force = read_vector3(r.required("force"), r.at("force"), kMaxForce);
        p.radius
            = read_number(r.required("radius"), r.at("radius"), Range { 0.0, kMaxRadius, true });
        if (const json* v = r.optional("duration")) {
            p.duration = read_number(*v, r.at("duration"), Range { 0.0, kMaxDuration, true });
        }
        return p;
    }
    case Method::RemoveForce:
        return RemoveForceParams { read_object_id(r, "id") };
    case Method::Grab: {
        GrabParams p;
        p.point = read_point(r, "point");
        if (const json* v = r.optional("stiffness")) {
            p.stiffness = read_number(*v, r.at("stiffness"), Range { 0.0, kMaxStiffness, true });
        }
        if (const json* v = r.optional("radius")) {
            p.radius = read_number(*v, r.at("radius"), Range { 0.0, kMaxRadius, true });
        }
        return p;
    }
    case Method::MoveGrab: {
        MoveGrabParams p;
        p.id = read_object_id(r, "id");
        p.target = read_point(r, "target");
        return p;
    }
    case Method::Release:
        return ReleaseParams { read_object_id(r, "id") };
    case Method::Cut:
        return CutParams { read_triangles(r, frames, limits) };
    case Method::Scalpel: {
        ScalpelParams p;
        p.stroke = read_stroke(r);
        p.a = read_point(r, "a");
        p.b = read_point(r, "b");
        if (p.a == p.b) {
            fail(kBad, r.at("b"), "blade endpoints a and b coincide");
        }
        return p;
    }
    case Method::EndStroke:
        return EndStrokeParams { read_stroke(r) };
    case Method::GetSurface:
        return GetSurfaceParams {};
    case Method::GetStats:
        return GetStatsParams {};
    case Method::Shutdown:
        return ShutdownParams {};
    case Method::ToolCreate:
        return read_tool_create(r);
    case Method::ToolMove: {
        ToolMoveParams p;
        p.id = read_object_id(r, "id");
        p.position = read_point(r, "position");
        p.orientation = read_orientation(r);
        return p;
    }
    case Method::ToolRemove:
        return ToolRemoveParams { read_object_id(r, "id") };
    }
    fail(ErrorCode::MethodNotFound, "/method", "unknown method");
}

json vector_json(const Vector3& v) {
    return json::array({ v[0], v[1], v[2] });
}

} // namespace

Params decode_params(Method method, const json* params, FrameSet& frames, const Limits& limits) {
    static const json kEmpty = json::object();
    ObjectReader reader(params == nullptr ? kEmpty : *params, kParams, kBad);
    Params out = decode_object(method, reader, frames, limits);
    reader.finish();
    return out;
}

json encode_params(const Params& params, const EncodeOptions& options, Message& frames) {
    json out = json::object();
    std::visit(
        [&](const auto& p) {
            using T = std::decay_t<decltype(p)>;
            if constexpr (std::is_same_v<T, HelloParams>) {
                if (p.client) {
                    out["client"] = *p.client;
                }
                if (p.protocol) {
                    out["protocol"] = *p.protocol;
                }
            } else if constexpr (std::is_same_v<T, LoadSceneParams>) {
                if (p.name) {
                    out["name"] = *p.name;
                }
                if (p.scene_json) {
                    out["scene"] = json::parse(*p.scene_json, nullptr, false);
                }
            } else if constexpr (std::is_same_v<T, StepParams>) {
                out["ticks"] = p.ticks;
            } else if constexpr (std::is_same_v<T, SetRateParams>) {
                out["hz"] = p.hz;
            } else if constexpr (std::is_same_v<T, ApplyForceParams>) {
                out["point"] = vector_json(p.point);
                out["force"] = vector_json(p.force);
                out["radius"] = p.radius;
                if (p.duration) {
                    out["duration"] = *p.duration;
                }
            } else if constexpr (std::is_same_v<T,
                                     RemoveForceParams> || std::is_same_v<T, ReleaseParams>) {
                out["id"] = p.id;
            } else if constexpr (std::is_same_v<T, GrabParams>) {
                out["point"] = vector_json(p.point);
                if (p.stiffness) {
                    out["stiffness"] = *p.stiffness;
                }
                if (p.radius) {
                    out["radius"] = *p.radius;
                }
            } else if constexpr (std::is_same_v<T, MoveGrabParams>) {
                out["id"] = p.id;
                out["target"] = vector_json(p.target);
            } else if constexpr (std::is_same_v<T, CutParams>) {
                if (options.binary_arrays) {
                    std::vector<float> flat;
                    flat.reserve(9 * p.triangles.size());
                    for (const auto& tri : p.triangles) {
                        for (const auto& corner : tri) {
                            for (double x : corner) {
                                flat.push_back(static_cast<float>(x));
                            }
                        }
                    }
                    frames.push_back(encode_array(std::span<const float>(flat)));
                    out["triangles"] = frame_ref_json(static_cast<std::uint32_t>(frames.size()),
                        DType::Float32, { p.triangles.size(), 3, 3 });
                } else {
                    json list = json::array();
                    for (const auto& tri : p.triangles) {
                        list.push_back(json::array(
                            { vector_json(tri[0]), vector_json(tri[1]), vector_json(tri[2]) }));
                    }
                    out["triangles"] = std::move(list);
                }
            } else if constexpr (std::is_same_v<T, ScalpelParams>) {
                out["stroke"] = p.stroke;
                out["a"] = vector_json(p.a);
                out["b"] = vector_json(p.b);
            } else if constexpr (std::is_same_v<T, EndStrokeParams>) {
                out["stroke"] = p.stroke;
            } else if constexpr (std::is_same_v<T, ToolCreateParams>) {
                out["shape"] = p.shape;
                if (p.radius) {
                    out["radius"] = *p.radius;
                }
                if (p.length) {
                    out["length"] = *p.length;
                }
                if (p.size) {
                    out["size"] = vector_json(*p.size);
                }
                out["position"] = vector_json(p.position);
                if (p.orientation) {
                    out["orientation"] = json(*p.orientation);
                }
                if (p.stiffness) {
                    out["stiffness"] = *p.stiffness;
                }
                if (p.friction) {
                    out["friction"] = *p.friction;
                }
            } else if constexpr (std::is_same_v<T, ToolMoveParams>) {
                out["id"] = p.id;
                out["position"] = vector_json(p.position);
                if (p.orientation) {
                    out["orientation"] = json(*p.orientation);
                }
            } else if constexpr (std::is_same_v<T, ToolRemoveParams>) {
                out["id"] = p.id;
            }
        },
        params);
    return out;
}

} // namespace polycut::protocol::detail

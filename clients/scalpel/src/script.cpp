// Scalpel script parsing and expansion into timed requests (see script.hpp).
#include "script.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace polycut::scalpel {

namespace {

using json = nlohmann::json;
using protocol::Vector3;

[[noreturn]] void fail(const std::string& pointer, const std::string& what) {
    throw ScriptError(pointer + ": " + what);
}

double number(const json& v, const std::string& pointer) {
    if (!v.is_number() || !std::isfinite(v.get<double>())) {
        fail(pointer, "must be a finite number");
    }
    return v.get<double>();
}

double number_or(const json& obj, const char* key, double fallback, const std::string& pointer) {
    return obj.contains(key) ? number(obj[key], pointer + "/" + key) : fallback;
}

Vector3 vec3(const json& v, const std::string& pointer) {
    if (!v.is_array() || v.size() != 3) {
        fail(pointer, "must be [x, y, z]");
    }
    return { number(v[0], pointer + "/0"), number(v[1], pointer + "/1"),
        number(v[2], pointer + "/2") };
}

const json& member(const json& obj, const char* key, const std::string& pointer) {
    if (!obj.is_object() || !obj.contains(key)) {
        fail(pointer, std::string("missing \"") + key + "\"");
    }
    return obj[key];
}

Vector3 lerp(const Vector3& a, const Vector3& b, double s) {
    return { a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2]) };
}

double distance(const Vector3& a, const Vector3& b) {
    return std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
}

/// The blade path of a stroke: a polyline, or an arc in a horizontal plane.
std::vector<Vector3> stroke_path(const json& s, const std::string& pointer) {
    std::vector<Vector3> path;
    if (s.contains("path")) {
        const json& p = s["path"];
        if (!p.is_array() || p.size() < 2) {
            fail(pointer + "/path", "must hold at least two points");
        }
        for (std::size_t i = 0; i < p.size(); ++i) {
            path.push_back(vec3(p[i], pointer + "/path/" + std::to_string(i)));
        }
    } else if (s.contains("arc")) {
        const json& a = s["arc"];
        const std::string ap = pointer + "/arc";
        const Vector3 c = vec3(member(a, "center", ap), ap + "/center");
        const double r = number(member(a, "radius", ap), ap + "/radius");
        const double d0 = number(member(a, "start_deg", ap), ap + "/start_deg");
        const double d1 = number(member(a, "end_deg", ap), ap + "/end_deg");
        const int n = 64;
        for (int i = 0; i <= n; ++i) {
            const double d = (d0 + (d1 - d0) * i / n) * M_PI / 180.0;
            path.push_back({ c[0] + r * std::cos(d), c[1] + r * std::sin(d), c[2] });
        }
    } else {
        fail(pointer, "a stroke needs \"path\" or \"arc\"");
    }
    return path;
}

/// The point at arc-length fraction s in [0, 1] of a polyline.
Vector3 along(const std::vector<Vector3>& path, double s) {
    double total = 0;
    for (std::size_t i = 1; i < path.size(); ++i) {
        total += distance(path[i - 1], path[i]);
    }
    double target = s * total;
    for (std::size_t i = 1; i < path.size(); ++i) {
        const double l = distance(path[i - 1], path[i]);
        if (target <= l || i + 1 == path.size()) {
            return lerp(path[i - 1], path[i], l > 0 ? std::min(1.0, target / l) : 0.0);
        }
        target -= l;
    }
    return path.back();
}

int sample_count(const json& e, double duration, const std::string& pointer) {
    if (e.contains("samples")) {
        const double n = number(e["samples"], pointer + "/samples");
        if (n < 2 || n > 100000) {
            fail(pointer + "/samples", "must be in [2, 100000]");
        }
        return static_cast<int>(n);
    }
    const double rate = number_or(e, "rate_hz", 30.0, pointer);
    if (!(rate > 0)) {
        fail(pointer + "/rate_hz", "must be > 0");
    }
    return std::max(2, static_cast<int>(std::ceil(duration * rate)) + 1);
}

struct Parser {
    Script script;
    std::map<std::string, Vector3> grab_targets;
    std::uint64_t next_stroke = 1;

    void add(double t, protocol::Params params, std::string bind_as = {}, std::string ref = {},
        bool wait = false) {
        script.actions.push_back(
            Action { t, std::move(params), std::move(bind_as), std::move(ref), wait });
        script.end_t = std::max(script.end_t, t);
    }

    void stroke(double t, const json& s, const std::string& p) {
        const std::uint64_t id = s.contains("id")
            ? static_cast<std::uint64_t>(number(s["id"], p + "/id"))
            : next_stroke;
        next_stroke = std::max(next_stroke, id + 1);
        const double duration = number_or(s, "duration", 1.0, p);
        if (!(duration >= 0)) {
            fail(p + "/duration", "must be >= 0");
        }
        const Vector3 blade = vec3(member(s, "blade", p), p + "/blade");
        const std::vector<Vector3> path = stroke_path(s, p);
        const int n = sample_count(s, duration, p);
        for (int i = 0; i < n; ++i) {
            const double f = double(i) / (n - 1);
            const Vector3 a = along(path, f);
            const Vector3 b = { a[0] + blade[0], a[1] + blade[1], a[2] + blade[2] };
            add(t + f * duration, protocol::ScalpelParams { id, a, b });
        }
        if (s.value("end", true)) {
            add(t + duration, protocol::EndStrokeParams { id });
        }
    }

    void move_grab(double t, const json& m, const std::string& p) {
        const json& g = member(m, "grab", p);
        if (!g.is_string()) {
            fail(p + "/grab", "must be the name given to a grab with \"as\"");
        }
        const std::string name = g.get<std::string>();
        if (!grab_targets.contains(name)) {
            fail(p + "/grab", "no grab named \"" + name + "\" before this event");
        }
        if (m.contains("target")) {
            const Vector3 target = vec3(m["target"], p + "/target");
            add(t, protocol::MoveGrabParams { 0, target }, {}, name);
            grab_targets[name] = target;
            return;
        }
        const Vector3 from = grab_targets[name];
        const Vector3 to = vec3(member(m, "to", p), p + "/to");
        const double duration = number_or(m, "duration", 1.0, p);
        const int n = sample_count(m, duration, p);
        for (int i = 1; i < n; ++i) {
            const double f = double(i) / (n - 1);
            add(t + f * duration, protocol::MoveGrabParams { 0, lerp(from, to, f) }, {}, name);
        }
        grab_targets[name] = to;
    }

    std::string name_of(const json& v, const std::string& p) {
        if (!v.is_string()) {
            fail(p, "must be a name given with \"as\"");
        }
        return v.get<std::string>();
    }

    void event(const json& e, const std::string& p) {
        if (!e.is_object()) {
            fail(p, "an event must be an object");
        }
        const double t = number(member(e, "t", p), p + "/t");
        if (t < 0) {
            fail(p + "/t", "must be >= 0");
        }
        const std::string as = e.value("as", std::string());
        if (e.contains("load_scene")) {
            const json& v = e["load_scene"];
            protocol::LoadSceneParams params;
            if (v.is_string()) {
                params.name = v.get<std::string>();
            } else if (v.is_object()) {
                params.scene_json = v.dump();
            } else {
                fail(p + "/load_scene", "must be a scene name or an inline scene object");
            }
            add(t, params, {}, {}, true);
        } else if (e.contains("reset")) {
            add(t, protocol::ResetParams {}, {}, {}, true);
        } else if (e.contains("set_rate")) {
            add(t, protocol::SetRateParams { number(e["set_rate"], p + "/set_rate") }, {}, {},
                true);
        } else if (e.contains("stroke")) {
            stroke(t, e["stroke"], p + "/stroke");
        } else if (e.contains("cut")) {
            const json& c = member(e["cut"], "triangles", p + "/cut");
            protocol::CutParams params;
            if (!c.is_array()) {
                fail(p + "/cut/triangles", "must be an array of triangles");
            }
            for (std::size_t k = 0; k < c.size(); ++k) {
                const std::string tp = p + "/cut/triangles/" + std::to_string(k);
                if (!c[k].is_array() || c[k].size() != 3) {
                    fail(tp, "must be three corners");
                }
                params.triangles.push_back({ vec3(c[k][0], tp + "/0"), vec3(c[k][1], tp + "/1"),
                    vec3(c[k][2], tp + "/2") });
            }
            add(t, params);
        } else if (e.contains("apply_force")) {
            const json& f = e["apply_force"];
            const std::string fp = p + "/apply_force";
            protocol::ApplyForceParams params;
            params.point = vec3(member(f, "point", fp), fp + "/point");
            params.force = vec3(member(f, "force", fp), fp + "/force");
            params.radius = number_or(f, "radius", 0.005, fp);
            if (f.contains("duration")) {
                params.duration = number(f["duration"], fp + "/duration");
            }
            add(t, params, as.empty() ? "force@" + p : as);
        } else if (e.contains("remove_force")) {
            add(t, protocol::RemoveForceParams {}, {}, name_of(e["remove_force"], p));
        } else if (e.contains("grab")) {
            const json& g = e["grab"];
            const std::string gp = p + "/grab";
            if (as.empty()) {
                fail(p + "/as", "a grab needs a name (\"as\") for its moves");
            }
            protocol::GrabParams params;
            params.point = vec3(member(g, "point", gp), gp + "/point");
            if (g.contains("stiffness")) {
                params.stiffness = number(g["stiffness"], gp + "/stiffness");
            }
            if (g.contains("radius")) {
                params.radius = number(g["radius"], gp + "/radius");
            }
            grab_targets[as] = params.point;
            add(t, params, as);
        } else if (e.contains("move_grab")) {
            move_grab(t, e["move_grab"], p + "/move_grab");
        } else if (e.contains("release")) {
            add(t, protocol::ReleaseParams {}, {}, name_of(e["release"], p + "/release"));
        } else if (e.contains("wait")) {
            script.end_t = std::max(script.end_t, t);
        } else {
            fail(p,
                "unknown event (expected load_scene, reset, set_rate, stroke, cut, "
                "apply_force, remove_force, grab, move_grab, release or wait)");
        }
    }
};

} // namespace

Script parse_script(const std::string& json_text) {
    json root;
    try {
        root = json::parse(json_text);
    } catch (const json::exception& e) {
        throw ScriptError(std::string("not JSON: ") + e.what());
    }
    if (!root.is_object()) {
        fail("", "a script must be a JSON object");
    }
    Parser parser;
    parser.script.name = root.value("name", std::string("script"));
    parser.script.description = root.value("description", std::string());
    const json& events = member(root, "events", "");
    if (!events.is_array()) {
        fail("/events", "must be an array");
    }
    for (std::size_t i = 0; i < events.size(); ++i) {
        parser.event(events[i], "/events/" + std::to_string(i));
    }
    std::stable_sort(parser.script.actions.begin(), parser.script.actions.end(),
        [](const Action& a, const Action& b) { return a.t < b.t; });
    return parser.script;
}

Script load_script(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw ScriptError(path + ": cannot open the script");
    }
    std::stringstream text;
    text << in.rdbuf();
    try {
        return parse_script(text.str());
    } catch (const ScriptError& e) {
        throw ScriptError(path + ": " + e.what());
    }
}

} // namespace polycut::scalpel

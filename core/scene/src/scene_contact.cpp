// Scene keys of issue 15 (docs/scenes.md): `obstacles` (rigid shapes the tissue rests on or is
// pressed against), `tools` (scripted tools), `contact` (penalty settings) and `embedded` (a
// detailed surface). Every field is checked where it is read.
#include "scene_contact.hpp"

namespace polycut::scene::detail {

namespace {
constexpr double kMaxLength = 1e3; // [m]
constexpr double kMaxStiffness = 1e13; // [N/m^3]

void positive_size(ObjectReader& r, const Vec3& size) {
    for (int i = 0; i < 3; ++i)
        if (!(size[i] > 0) || size[i] > kMaxLength)
            throw SceneError(r.child("size") + "/" + std::to_string(i), "must be in (0, 1000] [m]");
}

Obstacle parse_obstacle(const json& j, const std::string& ptr) {
    ObjectReader r(j, ptr);
    Obstacle o;
    o.kind = r.choice_required("type", kObstacleKind);
    o.name = r.string("name", "");
    if (o.kind == Obstacle::Kind::Plane) {
        o.point = r.vec3("point", o.point, true, "m");
        o.normal = r.vec3("normal", o.normal, true);
        if (!(o.normal.norm() > 0))
            r.fail("normal", "must be a non-zero vector");
        o.normal.normalize();
    } else if (o.kind == Obstacle::Kind::Box) {
        o.point = r.vec3("center", o.point, true, "m");
        o.size = r.vec3("size", o.size, true, "m");
        positive_size(r, o.size);
        o.rotation = r.vec3("rotation", o.rotation, false, "rad");
    } else if (o.kind == Obstacle::Kind::Sphere) {
        o.point = r.vec3("center", o.point, true, "m");
        o.radius = r.number_required("radius", 0, kMaxLength, true, "m");
    } else if (o.kind == Obstacle::Kind::Capsule) {
        o.a = r.vec3("a", o.a, true, "m");
        o.b = r.vec3("b", o.b, true, "m");
        o.radius = r.number_required("radius", 0, kMaxLength, true, "m");
    } else { // Mesh
        o.path = r.string("path", "");
        if (o.path.empty())
            r.fail("path", "is required (a closed surface file relative to the scene file)");
        o.scale = r.number("scale", 1.0, 0, kMaxLength, true);
        o.point = r.vec3("translation", o.point, false, "m");
        o.rotation = r.vec3("rotation", o.rotation, false, "rad");
    }
    for (int i = 0; i < 3; ++i)
        if (!(std::abs(o.point[i]) <= kMaxLength) || !(std::abs(o.a[i]) <= kMaxLength)
            || !(std::abs(o.b[i]) <= kMaxLength))
            r.fail("", "coordinates must be within [-1000, 1000] [m]");
    if (r.has("stiffness"))
        o.stiffness = r.number_required("stiffness", 0, kMaxStiffness, true, "N/m^3");
    if (r.has("friction"))
        o.friction = r.number_required("friction", 0, 10, false);
    r.finish();
    return o;
}
ScriptedTool parse_tool(const json& j, const std::string& ptr) {
    ObjectReader r(j, ptr);
    ScriptedTool t;
    t.shape = r.choice_required("shape", kToolShape);
    if (t.shape != ToolShape::Blade)
        t.radius = r.number_required("radius", 0, kMaxLength, true, "m");
    if (t.shape == ToolShape::Capsule)
        t.length = r.number_required("length", 0, kMaxLength, false, "m");
    if (t.shape == ToolShape::Blade) {
        t.size = r.vec3("size", t.size, true, "m");
        positive_size(r, t.size);
    }
    if (r.has("stiffness"))
        t.stiffness = r.number_required("stiffness", 0, kMaxStiffness, true, "N/m^3");
    if (r.has("friction"))
        t.friction = r.number_required("friction", 0, 10, false);
    const json& keys = r.get("keys");
    if (!keys.is_array() || keys.empty())
        r.fail("keys", "must be a non-empty array of {\"t\", \"position\", \"orientation\"}");
    for (std::size_t i = 0; i < keys.size(); ++i) {
        ObjectReader k(keys[i], r.child("keys") + "/" + std::to_string(i));
        ScriptedTool::Key key;
        key.t = k.number("t", 0, 0, 1e7, false, "s");
        if (!t.keys.empty() && !(key.t > t.keys.back().t))
            k.fail("t", "must be later than the previous key's");
        key.position = k.vec3("position", key.position, true, "m");
        if (!(key.position.cwiseAbs().maxCoeff() <= kMaxLength))
            k.fail("position", "coordinates must be within [-1000, 1000] [m]");
        if (k.has("orientation")) {
            const json& q = k.get("orientation");
            if (!q.is_array() || q.size() != 4)
                k.fail("orientation", "must be a quaternion [w, x, y, z]");
            for (int c = 0; c < 4; ++c) {
                if (!q[std::size_t(c)].is_number()
                    || !std::isfinite(q[std::size_t(c)].get<double>()))
                    throw SceneError(k.child("orientation") + "/" + std::to_string(c),
                        "must be a finite number");
                key.orientation[c] = q[std::size_t(c)].get<double>();
            }
            if (!(key.orientation.norm() > 1e-9))
                k.fail("orientation", "must not be the zero quaternion");
            key.orientation.normalize();
        }
        k.finish();
        t.keys.push_back(key);
    }
    r.finish();
    return t;
}
} // namespace

void parse_contact(ObjectReader& r, Scene& s) {
    if (r.has("tools")) {
        const json& arr = r.get("tools");
        if (!arr.is_array())
            r.fail("tools", "must be an array of scripted tools");
        for (std::size_t i = 0; i < arr.size(); ++i)
            s.tools.push_back(parse_tool(arr[i], r.child("tools") + "/" + std::to_string(i)));
    }
    if (r.has("obstacles")) {
        const json& arr = r.get("obstacles");
        if (!arr.is_array())
            r.fail("obstacles", "must be an array of obstacles");
        for (std::size_t i = 0; i < arr.size(); ++i)
            s.obstacles.push_back(
                parse_obstacle(arr[i], r.child("obstacles") + "/" + std::to_string(i)));
    }
    if (r.has("embedded")) {
        ObjectReader e(r.get("embedded"), r.child("embedded"));
        Embedded emb;
        emb.path = e.string("path", "");
        if (emb.path.empty())
            e.fail("path", "is required (a surface file relative to the scene file)");
        emb.scale = e.number("scale", 1.0, 0, kMaxLength, true);
        e.finish();
        s.embedded = emb;
    }
    if (r.has("contact")) {
        ObjectReader c(r.get("contact"), r.child("contact"));
        if (c.has("stiffness"))
            s.contact.stiffness = c.number_required("stiffness", 0, kMaxStiffness, true, "N/m^3");
        if (c.has("friction"))
            s.contact.friction = c.number_required("friction", 0, 10, false);
        s.contact.self_stiffness = c.number(
            "self_stiffness", s.contact.self_stiffness, 0, kMaxStiffness, false, "N/m^3");
        if (c.has("slip_velocity"))
            s.contact.slip_velocity = c.number_required("slip_velocity", 0, 10, true, "m/s");
        c.finish();
    }
}

} // namespace polycut::scene::detail

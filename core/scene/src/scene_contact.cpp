// Scene keys `obstacles` and `contact` (docs/scenes.md): rigid shapes the tissue rests on or is
// pressed against, and the penalty settings. Every field is checked where it is read.
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
    const std::string type = r.choice("type", "", { "plane", "box", "sphere", "capsule", "mesh" });
    o.name = r.string("name", "");
    if (type == "plane") {
        o.kind = Obstacle::Kind::Plane;
        o.point = r.vec3("point", o.point, true, "m");
        o.normal = r.vec3("normal", o.normal, true);
        if (!(o.normal.norm() > 0))
            r.fail("normal", "must be a non-zero vector");
        o.normal.normalize();
    } else if (type == "box") {
        o.kind = Obstacle::Kind::Box;
        o.point = r.vec3("center", o.point, true, "m");
        o.size = r.vec3("size", o.size, true, "m");
        positive_size(r, o.size);
        o.rotation = r.vec3("rotation", o.rotation, false, "rad");
    } else if (type == "sphere") {
        o.kind = Obstacle::Kind::Sphere;
        o.point = r.vec3("center", o.point, true, "m");
        o.radius = r.number_required("radius", 0, kMaxLength, true, "m");
    } else if (type == "capsule") {
        o.kind = Obstacle::Kind::Capsule;
        o.a = r.vec3("a", o.a, true, "m");
        o.b = r.vec3("b", o.b, true, "m");
        o.radius = r.number_required("radius", 0, kMaxLength, true, "m");
    } else {
        o.kind = Obstacle::Kind::Mesh;
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
} // namespace

void parse_contact(ObjectReader& r, Scene& s) {
    if (r.has("obstacles")) {
        const json& arr = r.get("obstacles");
        if (!arr.is_array())
            r.fail("obstacles", "must be an array of obstacles");
        for (std::size_t i = 0; i < arr.size(); ++i)
            s.obstacles.push_back(
                parse_obstacle(arr[i], r.child("obstacles") + "/" + std::to_string(i)));
    }
    if (r.has("contact")) {
        ObjectReader c(r.get("contact"), r.child("contact"));
        if (c.has("stiffness"))
            s.contact.stiffness = c.number_required("stiffness", 0, kMaxStiffness, true, "N/m^3");
        if (c.has("friction"))
            s.contact.friction = c.number_required("friction", 0, 10, false);
        if (c.has("slip_velocity"))
            s.contact.slip_velocity = c.number_required("slip_velocity", 0, 10, true, "m/s");
        c.finish();
    }
}

} // namespace polycut::scene::detail

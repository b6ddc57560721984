// Scene keys of an octree geometry (docs/scenes.md "octree").
#include "scene_octree.hpp"

#include <cmath>

namespace polycut::scene::detail {
namespace {
constexpr double kMaxLength = 1e3; // [m] anything larger is a unit mistake
constexpr int kMaxDepth = 10; // meshing::Octree::kMaxDepth
} // namespace

void parse_octree(ObjectReader& r, Geometry& g) {
    Geometry::OctreeSettings& o = g.octree;
    o.surface_cell_size = r.number("surface_cell_size", 0, 0, kMaxLength, false, "m");
    if (o.surface_cell_size > g.cell_size)
        r.fail("surface_cell_size", "must not exceed \"cell_size\" (0: cell_size)");
    if (o.object == OctreeObject::Box && r.has("surface_cell_size"))
        r.fail("surface_cell_size", "needs an object with a surface (\"shape\" or \"path\")");
    o.max_depth = int(r.integer("max_depth", o.max_depth, 0, kMaxDepth));
    o.keep = r.choice("keep", o.keep, kOctreeKeep);
    if (r.has("regions")) {
        const json& a = r.get("regions");
        if (!a.is_array())
            r.fail("regions", "must be an array of {\"lo\", \"hi\", \"cell_size\"} boxes [m]");
        for (std::size_t i = 0; i < a.size(); ++i) {
            ObjectReader rr(a[i], r.child("regions") + "/" + std::to_string(i));
            Geometry::OctreeRegion region;
            region.lo = rr.vec3("lo", region.lo, true, "m");
            region.hi = rr.vec3("hi", region.hi, true, "m");
            for (int k = 0; k < 3; ++k)
                if (!(region.hi[k] > region.lo[k]))
                    throw SceneError(rr.child("hi") + "/" + std::to_string(k),
                        "must be greater than lo/" + std::to_string(k) + " [m]");
            region.cell_size = rr.number_required("cell_size", 0, g.cell_size, true, "m");
            rr.finish();
            o.regions.push_back(region);
        }
    }
    // levels the surface and the regions need must fit under max_depth
    double finest = o.surface_cell_size > 0 ? o.surface_cell_size : g.cell_size;
    for (const auto& region : o.regions)
        finest = std::min(finest, region.cell_size);
    if (g.cell_size / finest > std::ldexp(1.0, o.max_depth) * (1 + 1e-9))
        r.fail("max_depth",
            "is too small for the finest cell size asked for (" + std::to_string(finest)
                + " m needs " + std::to_string(int(std::ceil(std::log2(g.cell_size / finest))))
                + " levels below cell_size)");
    o.refine_stress = r.number("refine_stress", 0, 0, 1e12, false, "Pa");
}

} // namespace polycut::scene::detail

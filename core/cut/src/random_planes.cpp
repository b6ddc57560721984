#include "polycut/cut/random_planes.hpp"

#include "polycut/cut/cutter.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <random>

namespace polycut::cut {

mesh::Mesh split_by_random_planes(
    const mesh::Mesh& input, int planes, unsigned seed, const RandomPlanesOptions& options) {
    mesh::Mesh m = input;
    Cutter cutter(m, options.cut);
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss(0, 1);
    std::uniform_real_distribution<double> uni(-1, 1);
    auto random_normal = [&] {
        Vec3 n;
        do
            n = Vec3(gauss(rng), gauss(rng), gauss(rng));
        while (n.norm() < 1e-6);
        return Vec3(n.normalized());
    };
    for (int p = 0; p < planes; ++p) {
        if (!options.one_cell_per_plane) {
            geometry::Aabb box;
            for (const Vec3& x : m.rest)
                box.extend(x);
            const Vec3 point = box.center()
                + 0.5 * box.extent().cwiseProduct(Vec3(uni(rng), uni(rng), uni(rng)));
            cutter.split_by_plane(point, random_normal());
            continue;
        }
        // A few attempts: snapping may leave a plane through a small cell with nothing to split.
        for (int attempt = 0; attempt < 10; ++attempt) {
            std::vector<double> volume(m.cells.size());
            for (Index c = 0; c < m.num_cells(); ++c)
                volume[std::size_t(c)] = m.cell_volume(c);
            std::discrete_distribution<Index> pick(volume.begin(), volume.end());
            const Index c = pick(rng);
            geometry::Aabb box;
            for (Index n : m.cells[std::size_t(c)].nodes)
                box.extend(m.rest[std::size_t(n)]);
            const Vec3 point = m.cell_centroid(c)
                + options.offset * box.extent().cwiseProduct(Vec3(uni(rng), uni(rng), uni(rng)));
            const Index one[] = { c };
            if (!cutter.split_by_plane(point, random_normal(), one).new_cells.empty())
                break;
        }
    }
    return m;
}

} // namespace polycut::cut

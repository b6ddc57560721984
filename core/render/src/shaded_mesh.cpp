// Shading normals split at creases and tag boundaries (see shaded_mesh.hpp). Around each vertex,
// the incident triangles are grouped by union-find over the smooth edges they share; each group
// becomes one render vertex whose normal is the area-weighted mean of its face normals.
#include "polycut/render/shaded_mesh.hpp"

#include "polycut/common/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace polycut::render {

void SurfaceArrays::validate() const {
    if (positions.size() % 3 != 0)
        throw InputError("/surface/positions", "size is not a multiple of 3");
    if (triangles.size() % 3 != 0)
        throw InputError("/surface/triangles", "size is not a multiple of 3");
    const std::size_t n_triangles = triangles.size() / 3;
    if (!tags.empty() && tags.size() != n_triangles)
        throw InputError("/surface/tags",
            "has " + std::to_string(tags.size()) + " entries for " + std::to_string(n_triangles)
                + " triangles");
    for (std::size_t i = 0; i < positions.size(); ++i)
        if (!std::isfinite(positions[i]))
            throw InputError("/surface/positions/" + std::to_string(i / 3),
                "vertex " + std::to_string(i / 3) + " is not finite");
    const std::size_t n_vertices = positions.size() / 3;
    for (std::size_t i = 0; i < triangles.size(); ++i)
        if (triangles[i] >= n_vertices)
            throw InputError("/surface/triangles/" + std::to_string(i / 3),
                "triangle " + std::to_string(i / 3) + " refers to vertex "
                    + std::to_string(triangles[i]) + " of " + std::to_string(n_vertices));
    for (std::size_t t = 0; t < tags.size(); ++t)
        if (tags[t] > static_cast<std::uint8_t>(SurfaceTag::Cut))
            throw InputError("/surface/tags/" + std::to_string(t),
                "unknown tag " + std::to_string(tags[t]) + " (0 interior, 1 skin, 2 cut)");
}

namespace {

/// Scratch arrays kept between calls so a steady frame loop does not allocate.
struct Workspace {
    std::vector<float> face_normals; // (#T x 3) cross products (2 x area x unit normal)
    std::vector<float> unit_normals; // (#T x 3), zero for degenerate triangles
    std::vector<std::uint32_t> offsets; // (#V + 1) CSR of vertex -> incident corners
    std::vector<std::uint32_t> corners; // 3 t + k for each incident corner
    std::vector<std::uint32_t> parent; // union-find over one vertex's fan
    std::vector<std::uint32_t> group_of; // render vertex of each fan root
    std::vector<std::pair<std::uint32_t, std::uint32_t>> others; // (other vertex, fan slot)
};

std::uint32_t find(std::vector<std::uint32_t>& parent, std::uint32_t i) {
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

void compute_face_normals(const SurfaceArrays& s, Workspace& w) {
    const std::size_t n_triangles = s.triangles.size() / 3;
    w.face_normals.resize(3 * n_triangles);
    w.unit_normals.resize(3 * n_triangles);
    for (std::size_t t = 0; t < n_triangles; ++t) {
        const float* p0 = &s.positions[3 * s.triangles[3 * t]];
        const float* p1 = &s.positions[3 * s.triangles[3 * t + 1]];
        const float* p2 = &s.positions[3 * s.triangles[3 * t + 2]];
        const float e1[3] = { p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2] };
        const float e2[3] = { p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2] };
        float* n = &w.face_normals[3 * t];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        float* u = &w.unit_normals[3 * t];
        for (int c = 0; c < 3; ++c)
            u[c] = length > 0 ? n[c] / length : 0.0f;
    }
}

void build_incidence(const SurfaceArrays& s, Workspace& w) {
    const std::size_t n_vertices = s.positions.size() / 3;
    w.offsets.assign(n_vertices + 1, 0);
    for (const std::uint32_t v : s.triangles)
        ++w.offsets[v + 1];
    for (std::size_t v = 0; v < n_vertices; ++v)
        w.offsets[v + 1] += w.offsets[v];
    w.corners.resize(s.triangles.size());
    w.parent.assign(w.offsets.begin(), w.offsets.end() - 1); // used as fill cursors
    for (std::size_t c = 0; c < s.triangles.size(); ++c)
        w.corners[w.parent[s.triangles[c]]++] = static_cast<std::uint32_t>(c);
}

} // namespace

void build_shaded_mesh(const SurfaceArrays& s, double crease_angle_deg, ShadedMesh& out) {
    thread_local Workspace w;
    compute_face_normals(s, w);
    build_incidence(s, w);

    const std::size_t n_vertices = s.positions.size() / 3;
    const float cos_crease = static_cast<float>(std::cos(
                                 std::clamp(crease_angle_deg, 0.0, 180.0) * std::numbers::pi / 180))
        - 1e-6f;
    auto tag_of = [&](std::uint32_t t) {
        return s.tags.empty() ? static_cast<std::uint8_t>(SurfaceTag::Skin) : s.tags[t];
    };

    out.positions.clear();
    out.normals.clear();
    out.tags.clear();
    out.source.clear();
    out.triangles.resize(s.triangles.size());

    for (std::size_t v = 0; v < n_vertices; ++v) {
        const std::uint32_t begin = w.offsets[v];
        const std::uint32_t m = w.offsets[v + 1] - begin;
        if (m == 0)
            continue;
        // The fan's edges through v: each other vertex of each incident triangle, with its slot.
        w.others.clear();
        for (std::uint32_t i = 0; i < m; ++i) {
            const std::uint32_t c = w.corners[begin + i];
            const std::uint32_t t = c / 3;
            w.others.emplace_back(s.triangles[3 * t + (c + 1) % 3], i);
            w.others.emplace_back(s.triangles[3 * t + (c + 2) % 3], i);
        }
        // Fans are small (about 6 triangles, 12 entries): insertion sort beats std::sort here.
        if (w.others.size() <= 32) {
            for (std::size_t i = 1; i < w.others.size(); ++i)
                for (std::size_t j = i; j > 0 && w.others[j] < w.others[j - 1]; --j)
                    std::swap(w.others[j], w.others[j - 1]);
        } else {
            std::sort(w.others.begin(), w.others.end());
        }
        w.parent.resize(m);
        for (std::uint32_t i = 0; i < m; ++i)
            w.parent[i] = i;
        // An edge (v, other) shared by exactly two triangles joins them if it is smooth.
        for (std::size_t e = 0; e < w.others.size();) {
            std::size_t run = e + 1;
            while (run < w.others.size() && w.others[run].first == w.others[e].first)
                ++run;
            if (run - e == 2) {
                const std::uint32_t i = w.others[e].second, j = w.others[e + 1].second;
                const std::uint32_t ti = w.corners[begin + i] / 3, tj = w.corners[begin + j] / 3;
                const float* ni = &w.unit_normals[3 * ti];
                const float* nj = &w.unit_normals[3 * tj];
                const float dot = ni[0] * nj[0] + ni[1] * nj[1] + ni[2] * nj[2];
                const bool degenerate = (ni[0] == 0 && ni[1] == 0 && ni[2] == 0)
                    || (nj[0] == 0 && nj[1] == 0 && nj[2] == 0);
                if (i != j && tag_of(ti) == tag_of(tj) && !degenerate && dot >= cos_crease)
                    w.parent[find(w.parent, i)] = find(w.parent, j);
            }
            e = run;
        }
        // One render vertex per group, numbered in order of first appearance (deterministic).
        w.group_of.assign(m, UINT32_MAX);
        for (std::uint32_t i = 0; i < m; ++i) {
            const std::uint32_t root = find(w.parent, i);
            const std::uint32_t c = w.corners[begin + i];
            const std::uint32_t t = c / 3;
            if (w.group_of[root] == UINT32_MAX) {
                w.group_of[root] = static_cast<std::uint32_t>(out.source.size());
                out.source.push_back(static_cast<std::uint32_t>(v));
                out.tags.push_back(tag_of(t));
                out.positions.insert(
                    out.positions.end(), &s.positions[3 * v], &s.positions[3 * v] + 3);
                out.normals.insert(out.normals.end(), 3, 0.0f);
            }
            const std::uint32_t r = w.group_of[root];
            for (int k = 0; k < 3; ++k)
                out.normals[3 * r + k] += w.face_normals[3 * t + k]; // area weighting
            out.triangles[c] = r;
        }
    }
    for (std::size_t r = 0; r < out.source.size(); ++r) {
        float* n = &out.normals[3 * r];
        const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (length > 0 && std::isfinite(length)) {
            n[0] /= length, n[1] /= length, n[2] /= length;
        } else {
            n[0] = 0, n[1] = 0, n[2] = 1;
        }
    }
}

} // namespace polycut::render

// Shading normals split at creases and tag boundaries (see shaded_mesh.hpp). Around each vertex,
// the incident triangles are grouped by union-find over the smooth edges they share; each group
// becomes one render vertex whose normal is the area-weighted mean of its face normals. The
// incidence and the candidate edge pairs depend only on triangles and tags: they are cached and
// rebuilt only when those change, so a frame of a deforming surface with a fixed topology does
// the face normals, one crease test per candidate pair and the grouping.
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

/// Scratch arrays kept between calls so a steady frame loop does not allocate, and the part of
/// the work that depends only on the topology (triangles and tags), reused while they repeat.
struct Workspace {
    std::vector<float> face_normals; // (#T x 3) cross products (2 x area x unit normal)
    std::vector<float> unit_normals; // (#T x 3), zero for degenerate triangles
    std::vector<std::uint32_t> offsets; // (#V + 1) CSR of vertex -> incident corners
    std::vector<std::uint32_t> corners; // 3 t + k for each incident corner
    std::vector<std::uint32_t> parent; // union-find over one vertex's fan
    std::vector<std::uint32_t> group_of; // render vertex of each fan root
    std::vector<std::pair<std::uint32_t, std::uint32_t>> others; // (other vertex, fan slot)
    // Topology cache: for each vertex (CSR pair_offsets), the pairs of fan slots whose
    // triangles share an edge through it (manifold, not the same triangle, same tag); only the
    // crease test of such a pair depends on the positions.
    std::vector<std::uint32_t> pair_offsets; // (#V + 1)
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs; // fan slots (i, j)
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pair_triangles; // their triangles
    // Partition cache: which pairs were joined last time and the grouping that gave.
    std::vector<std::uint8_t> joined, last_joined;
    std::vector<std::uint32_t> part_triangles, part_source;
    std::vector<std::uint8_t> part_tags;
    bool partition_valid = false;
    std::vector<std::uint32_t> cached_triangles; // the input the cache was built for
    std::vector<std::uint8_t> cached_tags;
    std::size_t cached_vertices = 0;
    bool cache_valid = false;
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

namespace {

bool same_topology(const SurfaceArrays& s, const Workspace& w) {
    return w.cache_valid && w.cached_vertices == s.positions.size() / 3
        && std::equal(s.triangles.begin(), s.triangles.end(), w.cached_triangles.begin(),
            w.cached_triangles.end())
        && std::equal(s.tags.begin(), s.tags.end(), w.cached_tags.begin(), w.cached_tags.end());
}

/// Builds the incidence CSR and, per vertex, the smooth-candidate slot pairs of its fan.
template <typename TagOf> void build_topology(const SurfaceArrays& s, TagOf tag_of, Workspace& w) {
    build_incidence(s, w);
    const std::size_t n_vertices = s.positions.size() / 3;
    w.pair_offsets.assign(n_vertices + 1, 0);
    w.pairs.clear();
    w.pair_triangles.clear();
    for (std::size_t v = 0; v < n_vertices; ++v) {
        const std::uint32_t begin = w.offsets[v];
        const std::uint32_t m = w.offsets[v + 1] - begin;
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
        // An edge (v, other) shared by exactly two triangles of one tag may join them.
        for (std::size_t e = 0; e < w.others.size();) {
            std::size_t run = e + 1;
            while (run < w.others.size() && w.others[run].first == w.others[e].first)
                ++run;
            if (run - e == 2) {
                const std::uint32_t i = w.others[e].second, j = w.others[e + 1].second;
                const std::uint32_t ti = w.corners[begin + i] / 3, tj = w.corners[begin + j] / 3;
                if (i != j && tag_of(ti) == tag_of(tj)) {
                    w.pairs.emplace_back(i, j);
                    w.pair_triangles.emplace_back(ti, tj);
                }
            }
            e = run;
        }
        w.pair_offsets[v + 1] = static_cast<std::uint32_t>(w.pairs.size());
    }
    w.cached_triangles.assign(s.triangles.begin(), s.triangles.end());
    w.cached_tags.assign(s.tags.begin(), s.tags.end());
    w.cached_vertices = n_vertices;
    w.cache_valid = true;
    w.partition_valid = false;
}

/// Which candidate pairs are smooth now: neither triangle degenerate, normals within the crease.
void test_pairs(float cos_crease, Workspace& w) {
    w.joined.resize(w.pairs.size());
    for (std::size_t p = 0; p < w.pairs.size(); ++p) {
        const auto [ti, tj] = w.pair_triangles[p];
        const float* ni = &w.unit_normals[3 * ti];
        const float* nj = &w.unit_normals[3 * tj];
        const float dot = ni[0] * nj[0] + ni[1] * nj[1] + ni[2] * nj[2];
        const bool degenerate
            = (ni[0] == 0 && ni[1] == 0 && ni[2] == 0) || (nj[0] == 0 && nj[1] == 0 && nj[2] == 0);
        w.joined[p] = !degenerate && dot >= cos_crease;
    }
}

/// Groups each vertex's fan by union-find over the joined pairs into render vertices
/// (out.source, out.tags, out.triangles) and remembers the result.
template <typename TagOf>
void build_partition(const SurfaceArrays& s, TagOf tag_of, Workspace& w, ShadedMesh& out) {
    const std::size_t n_vertices = s.positions.size() / 3;
    out.source.clear();
    out.tags.clear();
    out.triangles.resize(s.triangles.size());
    for (std::size_t v = 0; v < n_vertices; ++v) {
        const std::uint32_t begin = w.offsets[v];
        const std::uint32_t m = w.offsets[v + 1] - begin;
        if (m == 0)
            continue;
        w.parent.resize(m);
        for (std::uint32_t i = 0; i < m; ++i)
            w.parent[i] = i;
        for (std::uint32_t p = w.pair_offsets[v]; p < w.pair_offsets[v + 1]; ++p)
            if (w.joined[p]) {
                const auto [i, j] = w.pairs[p];
                w.parent[find(w.parent, i)] = find(w.parent, j);
            }
        // One render vertex per group, numbered in order of first appearance (deterministic).
        w.group_of.assign(m, UINT32_MAX);
        for (std::uint32_t i = 0; i < m; ++i) {
            const std::uint32_t root = find(w.parent, i);
            const std::uint32_t c = w.corners[begin + i];
            if (w.group_of[root] == UINT32_MAX) {
                w.group_of[root] = static_cast<std::uint32_t>(out.source.size());
                out.source.push_back(static_cast<std::uint32_t>(v));
                out.tags.push_back(tag_of(c / 3));
            }
            out.triangles[c] = w.group_of[root];
        }
    }
    w.part_triangles = out.triangles;
    w.part_source = out.source;
    w.part_tags = out.tags;
    w.last_joined = w.joined;
    w.partition_valid = true;
}

} // namespace

void build_shaded_mesh(const SurfaceArrays& s, double crease_angle_deg, ShadedMesh& out) {
    thread_local Workspace w;
    auto tag_of = [&](std::uint32_t t) {
        return s.tags.empty() ? static_cast<std::uint8_t>(SurfaceTag::Skin) : s.tags[t];
    };
    compute_face_normals(s, w);
    if (!same_topology(s, w))
        build_topology(s, tag_of, w);
    const float cos_crease = static_cast<float>(std::cos(
                                 std::clamp(crease_angle_deg, 0.0, 180.0) * std::numbers::pi / 180))
        - 1e-6f;
    test_pairs(cos_crease, w);
    if (w.partition_valid && w.joined == w.last_joined) {
        // Same smooth groups as last time (the usual frame): reuse the grouping.
        out.triangles = w.part_triangles;
        out.source = w.part_source;
        out.tags = w.part_tags;
    } else {
        build_partition(s, tag_of, w, out);
    }

    // Positions, and normals as area-weighted sums over each render vertex's triangles (summed
    // in corner order, the same order whichever path built the grouping).
    const std::size_t n_render = out.source.size();
    out.positions.resize(3 * n_render);
    for (std::size_t r = 0; r < n_render; ++r)
        std::copy_n(&s.positions[3 * std::size_t(out.source[r])], 3, &out.positions[3 * r]);
    out.normals.assign(3 * n_render, 0.0f);
    for (std::size_t c = 0; c < out.triangles.size(); ++c) {
        float* n = &out.normals[3 * std::size_t(out.triangles[c])];
        const float* f = &w.face_normals[3 * (c / 3)];
        n[0] += f[0], n[1] += f[1], n[2] += f[2];
    }
    for (std::size_t r = 0; r < n_render; ++r) {
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

// Splitting the embedded surface along a cut (split.hpp). Outline:
// 1. the cut surface: the listed Cut faces, one copy per rest polygon (both lips of a cut are
//    the same polygon), fanned into triangles;
// 2. the patch: the skin triangles whose boxes meet a cut triangle's, plus every triangle
//    around their vertices (so a vertex the cut can reach has its whole fan in the patch),
//    welded by rest position (copies from earlier cuts become one vertex again; the edges
//    between them are kept as constraints);
// 3. CGAL corefines patch and cut (corefine.cpp): afterwards no triangle crosses the other mesh;
// 4. around each patch vertex the triangles are grouped across unconstrained edges: one group,
//    one vertex; a vertex on the cut has one group per side, so one copy per side, located by
//    a probe a little into its side's triangle;
// 5. the cut triangles inside the loaded surface become lips, once per Cut face (that is, per
//    side, outward for the face's cell): their corners are the skin's copies on the face's
//    side, or a vertex per mesh node;
// 6. the new and regrouped vertices (and the caller's) are embedded again.
#include "polycut/embed/split.hpp"

#include "corefine.hpp"
#include "cut_surface.hpp"
#include "polycut/common/error.hpp"
#include "polycut/common/stats.hpp"
#include "polycut/geometry/polygon.hpp"

#include <algorithm>
#include <numeric>
#include <set>

namespace polycut::embed {

namespace {

using detail::Box;
using detail::Key;
using detail::key_of;

/// How far into its side a probe sits, as a fraction of the way to a triangle's centroid.
constexpr double kProbeStep = 1e-3;

/// The copy among `ids` whose probe lies furthest on the -n side of its rest position: the
/// copy in the material behind a face of outward normal n.
std::uint32_t copy_behind(
    const Embedding& e, const std::vector<std::uint32_t>& ids, const Vec3& n) {
    std::uint32_t best = ids.front();
    double lowest = std::numeric_limits<double>::infinity();
    for (const std::uint32_t id : ids) {
        const double s = (e.probes[id] - e.rest[id]).dot(n);
        if (s < lowest) {
            lowest = s;
            best = id;
        }
    }
    return best;
}

/// Triangle t's rest-space normal (not normalized).
Vec3 rest_normal(const Embedding& e, std::size_t t) {
    const Vec3 &a = e.rest[e.triangles[3 * t]], &b = e.rest[e.triangles[3 * t + 1]],
               &c = e.rest[e.triangles[3 * t + 2]];
    return (b - a).cross(c - a);
}

/// Appends a vertex with its probe (weights come from the re-embedding).
std::uint32_t add_vertex(Embedding& e, const Vec3& rest, const Vec3& probe) {
    e.rest.push_back(rest);
    e.probes.push_back(probe);
    e.cells.push_back(kNone);
    return std::uint32_t(e.rest.size() - 1);
}

/// A cell that has node n (the first found), kNone if none.
std::map<Index, Index> cells_of(const mesh::Mesh& mesh, const std::set<Index>& nodes) {
    std::map<Index, Index> out;
    for (Index c = 0; c < mesh.num_cells() && out.size() < nodes.size(); ++c)
        for (const Index n : mesh.cells[std::size_t(c)].nodes)
            if (nodes.count(n))
                out.emplace(n, c);
    return out;
}

/// Lip corners at nodes the cut separated: the node's lip vertex gets a twin for the copy, and
/// every lip triangle at it takes the one on its side (the probe behind its normal).
void separate_lip_nodes(Embedding& e, SplitState& state, const mesh::Mesh& mesh,
    const std::vector<std::pair<Index, Index>>& duplicated, std::vector<std::uint32_t>& reembed,
    SplitReport& report) {
    std::set<Index> nodes;
    for (const auto& [n, copy] : duplicated)
        if (state.node_vertex.count(n))
            nodes.insert({ n, copy });
    if (nodes.empty())
        return;
    const std::map<Index, Index> cell = cells_of(mesh, nodes);
    auto probe_into = [&](Index node) {
        const Vec3& p = mesh.rest[std::size_t(node)];
        const auto it = cell.find(node);
        return it == cell.end() ? p : Vec3(p + kProbeStep * (mesh.cell_centroid(it->second) - p));
    };
    std::map<std::uint32_t, std::array<std::uint32_t, 2>> twins; // old vertex -> (node's, copy's)
    for (const auto& [n, copy] : duplicated) {
        const auto it = state.node_vertex.find(n);
        if (it == state.node_vertex.end())
            continue;
        const std::uint32_t v = it->second;
        e.probes[v] = probe_into(n);
        const std::uint32_t w = add_vertex(e, mesh.rest[std::size_t(copy)], probe_into(copy));
        ++report.vertices_added;
        state.node_vertex[copy] = w;
        twins[v] = { v, w };
        reembed.push_back(v);
        reembed.push_back(w);
    }
    for (std::size_t t = 0; t < e.lip.size(); ++t) {
        if (!e.lip[t])
            continue;
        const Vec3 n = rest_normal(e, t);
        for (int k = 0; k < 3; ++k) {
            std::uint32_t& g = e.triangles[3 * t + std::size_t(k)];
            if (const auto it = twins.find(g); it != twins.end())
                g = copy_behind(e, { it->second[0], it->second[1] }, n);
        }
    }
}

} // namespace

SplitReport split_along_cut(Embedding& e, SplitState& state, const mesh::Mesh& mesh,
    const CutChange& change, const std::function<bool(const Vec3&)>& inside,
    basis::PolyBasis poly) {
    const std::vector<Index>& cut_faces = change.cut_faces;
    const Stopwatch watch;
    SplitReport report;
    if (e.probes.empty())
        e.probes = e.rest;
    const std::size_t num_tri = e.triangles.size() / 3;
    if (e.lip.empty())
        e.lip.assign(num_tri, 0);

    // 1. The cut surface: one side's Cut faces. The two lips of a cut cover the same rest
    // surface, but not always with the same polygons (a node where the blade stopped inside a
    // cell sits on one side's face only), so the faces are parted into the two sides and one
    // side is taken: faces sharing an edge are on the same side when their normals agree (on
    // opposite sides across the crack front, where the lips fold), and a face whose rest
    // polygon is another's is on the other side (parity union-find).
    detail::CutSurface surface = detail::build_cut_surface(mesh, cut_faces);
    const std::vector<Index>& faces = surface.faces;
    const std::vector<Vec3>& normal = surface.normal;
    const detail::TriangleSet& cut = surface.cut;
    const std::vector<std::size_t>& cut_face = surface.triangle_face;
    const std::vector<Box>& cut_box = surface.triangle_box;
    const Box& all = surface.all;
    const auto& side_node = surface.side_node;
    report.cut_faces = faces.size();
    report.cut_triangles = cut.triangles.size();
    // Over an earlier cut (a Cut face that grew, or new faces meeting earlier ones): the caller
    // splits anew along all the Cut faces at once (decision 0033). Nothing has changed yet.
    if (!state.copies.empty() && !cut.triangles.empty()
        && detail::meets_earlier_cut(surface, mesh, change.cut_faces, state.copies)) {
        report.overlaps_earlier_cut = true;
        report.total_ms = watch.ms();
        return report;
    }
    std::vector<std::uint32_t> reembed_list = change.reembed;
    separate_lip_nodes(e, state, mesh, change.duplicated, reembed_list, report);
    if (cut.triangles.empty()) {
        reembed(e, mesh, reembed_list, poly);
        report.reembedded = reembed_list.size();
        report.total_ms = watch.ms();
        return report;
    }
    const double size = (all.hi - all.lo).norm();
    const double pad = 1e-9 * size;

    // 2. The patch: skin triangles near the cut, and the fans of their vertices.
    const std::size_t num_vertices = e.rest.size();
    std::vector<std::uint32_t> fan_offsets(num_vertices + 1, 0), fan;
    for (std::size_t t = 0; t < num_tri; ++t)
        if (!e.lip[t])
            for (int k = 0; k < 3; ++k)
                ++fan_offsets[e.triangles[3 * t + std::size_t(k)] + 1];
    std::partial_sum(fan_offsets.begin(), fan_offsets.end(), fan_offsets.begin());
    fan.resize(fan_offsets[num_vertices]);
    {
        std::vector<std::uint32_t> fill(fan_offsets.begin(), fan_offsets.end() - 1);
        for (std::size_t t = 0; t < num_tri; ++t)
            if (!e.lip[t])
                for (int k = 0; k < 3; ++k)
                    fan[fill[e.triangles[3 * t + std::size_t(k)]]++] = std::uint32_t(t);
    }
    std::vector<char> in_patch(num_tri, 0);
    std::vector<std::uint32_t> patch_tris;
    std::set<std::uint32_t> near_vertices;
    for (std::size_t t = 0; t < num_tri; ++t) {
        if (e.lip[t])
            continue;
        Box box;
        for (int k = 0; k < 3; ++k)
            box.add(e.rest[e.triangles[3 * t + std::size_t(k)]]);
        if (!box.overlaps(all, pad))
            continue;
        bool hit = false;
        for (const Box& b : cut_box)
            if (box.overlaps(b, pad)) {
                hit = true;
                break;
            }
        if (!hit)
            continue;
        for (int k = 0; k < 3; ++k)
            near_vertices.insert(e.triangles[3 * t + std::size_t(k)]);
    }
    // Copies of the near vertices (their triangles belong to the same welded fan).
    auto copies_of = [&](std::uint32_t v) -> std::vector<std::uint32_t> {
        const auto it = state.copies.find(key_of(e.rest[v]));
        if (it == state.copies.end())
            return { v };
        return it->second;
    };
    {
        std::set<std::uint32_t> with_copies;
        for (const std::uint32_t v : near_vertices)
            for (const std::uint32_t c : copies_of(v))
                with_copies.insert(c);
        for (const std::uint32_t v : with_copies)
            for (std::uint32_t k = fan_offsets[v]; k < fan_offsets[v + 1]; ++k)
                if (!in_patch[fan[k]]) {
                    in_patch[fan[k]] = 1;
                    patch_tris.push_back(fan[k]);
                }
    }
    std::sort(patch_tris.begin(), patch_tris.end());
    report.patch_triangles = patch_tris.size();

    // Welded patch vertices; a welded vertex is interior when all triangles of all its copies
    // are in the patch.
    detail::TriangleSet patch;
    std::map<Key, std::uint32_t> local_of;
    std::vector<std::vector<std::uint32_t>> ids_at; // global ids at each welded vertex
    for (const std::uint32_t t : patch_tris) {
        std::array<std::uint32_t, 3> tri {};
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t g = e.triangles[3 * t + std::size_t(k)];
            const auto [it, fresh]
                = local_of.emplace(key_of(e.rest[g]), std::uint32_t(patch.points.size()));
            if (fresh) {
                patch.points.push_back(e.rest[g]);
                ids_at.push_back(copies_of(g));
            }
            tri[std::size_t(k)] = it->second;
        }
        patch.triangles.push_back(tri);
    }
    const std::size_t num_welded = patch.points.size();
    std::vector<char> interior(num_welded, 1);
    for (std::size_t w = 0; w < num_welded; ++w)
        for (const std::uint32_t g : ids_at[w])
            for (std::uint32_t k = fan_offsets[g]; k < fan_offsets[g + 1]; ++k)
                if (!in_patch[fan[k]])
                    interior[w] = 0;
    // Seams of earlier cuts: welded edges whose two triangles name different vertices.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> seams;
    {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<std::uint32_t, std::uint32_t>>
            seen;
        for (std::size_t i = 0; i < patch_tris.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                std::uint32_t a = patch.triangles[i][std::size_t(k)],
                              b = patch.triangles[i][std::size_t((k + 1) % 3)];
                std::uint32_t ga = e.triangles[3 * patch_tris[i] + std::size_t(k)],
                              gb = e.triangles[3 * patch_tris[i] + std::size_t((k + 1) % 3)];
                if (a > b) {
                    std::swap(a, b);
                    std::swap(ga, gb);
                }
                const auto [it, fresh] = seen.emplace(std::make_pair(a, b), std::make_pair(ga, gb));
                if (!fresh && it->second != std::make_pair(ga, gb))
                    seams.emplace_back(a, b);
            }
    }

    // The cut meets the skin's vertices exactly where it passes them within rounding.
    detail::fit_to_skin(surface, patch.points);

    // 3. Corefinement.
    const Stopwatch cgal_watch;
    const detail::Corefined refined = detail::corefine_patch(patch, cut, seams, surface.tolerance);
    report.corefine_ms = cgal_watch.ms();
    const detail::TriangleSet& rp = refined.patch;
    // The skin parts along its crossings with the cut, except where a crossing runs along the
    // cut's own border (the crack front, where both sides share their nodes): there the
    // material is whole, and a seam would open a slit that no lip closes.
    std::set<std::pair<Key, Key>> cut_border;
    {
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
        for (const auto& tri : refined.cut.triangles)
            for (int k = 0; k < 3; ++k)
                ++uses[std::minmax(tri[std::size_t(k)], tri[std::size_t((k + 1) % 3)])];
        for (const auto& [edge, n] : uses)
            if (n == 1)
                cut_border.insert(std::minmax(key_of(refined.cut.points[edge.first]),
                    key_of(refined.cut.points[edge.second])));
    }
    std::set<std::pair<std::uint32_t, std::uint32_t>> constrained;
    for (const auto& [u, v] : refined.constrained)
        if (!cut_border.count(std::minmax(key_of(rp.points[u]), key_of(rp.points[v]))))
            constrained.emplace(u, v);
    auto is_constrained = [&](std::uint32_t a, std::uint32_t b) {
        return constrained.count({ std::min(a, b), std::max(a, b) }) > 0;
    };

    // 4. Vertex copies per group of triangles around each refined vertex.
    const std::size_t nv = rp.points.size(), nt = rp.triangles.size();
    std::vector<std::vector<std::uint32_t>> around(nv);
    for (std::size_t t = 0; t < nt; ++t)
        for (const std::uint32_t v : rp.triangles[t])
            around[v].push_back(std::uint32_t(t));
    std::vector<std::array<std::uint32_t, 3>> out_tris(nt);
    std::vector<std::vector<std::uint32_t>> copies_at(nv); // global ids of refined vertex w
    std::vector<char> regrouped(nv, 0);
    std::set<std::uint32_t> to_embed(reembed_list.begin(), reembed_list.end());
    const std::size_t vertices_before = e.rest.size();
    // The global id the input triangle `origin` had at position p (kNone-like ~0u if none).
    auto old_id = [&](std::uint32_t origin, const Vec3& p) {
        const std::uint32_t t = patch_tris[origin];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t g = e.triangles[3 * t + std::size_t(k)];
            if (e.rest[g] == p)
                return g;
        }
        return ~0u;
    };
    auto corner = [](const std::array<std::uint32_t, 3>& tri, std::uint32_t v) {
        return tri[0] == v ? 0 : tri[1] == v ? 1 : 2;
    };
    for (std::uint32_t w = 0; w < nv; ++w) {
        const std::vector<std::uint32_t>& tris = around[w];
        if (tris.empty())
            continue;
        const Vec3& p = rp.points[w];
        if (w < num_welded && !interior[w]) {
            // Border of the patch: untouched triangles, their own vertex.
            for (const std::uint32_t t : tris) {
                const std::uint32_t g = old_id(rp.origin[t], p);
                out_tris[t][std::size_t(corner(rp.triangles[t], w))] = g;
                if (std::find(copies_at[w].begin(), copies_at[w].end(), g) == copies_at[w].end())
                    copies_at[w].push_back(g);
            }
            continue;
        }
        // Groups: union of triangles sharing an unconstrained edge at w.
        std::vector<std::uint32_t> group(tris.size());
        std::iota(group.begin(), group.end(), 0u);
        auto find = [&](std::uint32_t i) {
            while (group[i] != i)
                i = group[i] = group[group[i]];
            return i;
        };
        bool on_cut = false;
        std::map<std::uint32_t, std::uint32_t> first_with; // other end -> triangle slot
        for (std::uint32_t i = 0; i < tris.size(); ++i)
            for (const std::uint32_t x : rp.triangles[tris[i]]) {
                if (x == w)
                    continue;
                if (is_constrained(w, x)) {
                    on_cut = true;
                    continue;
                }
                const auto [it, fresh] = first_with.emplace(x, i);
                if (!fresh)
                    group[find(i)] = find(it->second);
            }
        std::map<std::uint32_t, std::vector<std::uint32_t>> groups;
        for (std::uint32_t i = 0; i < tris.size(); ++i)
            groups[find(i)].push_back(tris[i]);
        std::set<std::uint32_t> used;
        for (auto& [root, members] : groups) {
            std::uint32_t g = ~0u;
            for (const std::uint32_t t : members)
                if (const std::uint32_t o = old_id(rp.origin[t], p); o != ~0u && !used.count(o)) {
                    g = o;
                    break;
                }
            const Vec3& q = rp.points[rp.triangles[members.front()][0]];
            const Vec3& r = rp.points[rp.triangles[members.front()][1]];
            const Vec3& s = rp.points[rp.triangles[members.front()][2]];
            const Vec3 probe
                = on_cut && groups.size() > 1 ? Vec3(p + kProbeStep * ((q + r + s) / 3.0 - p)) : p;
            if (g == ~0u) {
                g = add_vertex(e, p, probe);
                ++report.vertices_added;
            } else {
                e.probes[g] = probe;
            }
            used.insert(g);
            if (on_cut)
                to_embed.insert(g);
            for (const std::uint32_t t : members)
                out_tris[t][std::size_t(corner(rp.triangles[t], w))] = g;
            copies_at[w].push_back(g);
        }
        if (on_cut)
            regrouped[w] = 1;
        if (copies_at[w].size() > 1)
            state.copies[key_of(p)] = copies_at[w];
    }

    // Old lips whose corners were regrouped pick the copy on their side again.
    std::map<Key, std::uint32_t> refined_at;
    for (std::uint32_t w = 0; w < nv; ++w)
        if (!around[w].empty())
            refined_at.emplace(key_of(rp.points[w]), w);
    for (std::size_t t = 0; t < num_tri; ++t) {
        if (!e.lip[t])
            continue;
        const Vec3 n = rest_normal(e, t);
        for (int k = 0; k < 3; ++k) {
            std::uint32_t& g = e.triangles[3 * t + std::size_t(k)];
            const auto it = refined_at.find(key_of(e.rest[g]));
            if (it != refined_at.end() && regrouped[it->second] && copies_at[it->second].size() > 1)
                g = copy_behind(e, copies_at[it->second], n);
        }
    }

    // The skin: patch triangles out, refined triangles in.
    {
        std::vector<std::uint32_t> triangles;
        std::vector<std::uint8_t> lip;
        triangles.reserve(e.triangles.size() + 3 * nt);
        for (std::size_t t = 0; t < num_tri; ++t) {
            if (in_patch[t])
                continue;
            for (int k = 0; k < 3; ++k)
                triangles.push_back(e.triangles[3 * t + std::size_t(k)]);
            lip.push_back(e.lip[t]);
        }
        for (const auto& tri : out_tris) {
            triangles.insert(triangles.end(), tri.begin(), tri.end());
            lip.push_back(0);
        }
        report.skin_triangles_added = nt - patch_tris.size();
        e.triangles = std::move(triangles);
        e.lip = std::move(lip);
    }

    // 5. Lips: the cut inside the loaded surface, once per side. Lips an earlier cut made on
    // these polygons (a Cut face that grew by merging with a new one) are made again.
    {
        std::vector<std::uint32_t> triangles;
        std::vector<std::uint8_t> lip;
        for (std::size_t t = 0; t < e.lip.size(); ++t) {
            if (e.lip[t]) {
                const Vec3 centroid = (e.rest[e.triangles[3 * t]] + e.rest[e.triangles[3 * t + 1]]
                                          + e.rest[e.triangles[3 * t + 2]])
                    / 3.0;
                bool on_cut = false;
                for (std::size_t c = 0; c < cut.triangles.size() && !on_cut; ++c) {
                    const auto& tri = cut.triangles[c];
                    on_cut = detail::on_triangle(
                        centroid, cut.points[tri[0]], cut.points[tri[1]], cut.points[tri[2]], 1e-9);
                }
                if (on_cut) {
                    ++report.lips_remade;
                    continue;
                }
            }
            for (int k = 0; k < 3; ++k)
                triangles.push_back(e.triangles[3 * t + std::size_t(k)]);
            lip.push_back(e.lip[t]);
        }
        e.triangles = std::move(triangles);
        e.lip = std::move(lip);
    }
    // Lip corners that are no skin vertex: the mesh node there (a vertex per node), else (a
    // node of one side's polygons only) a vertex per side, located a little into that side.
    std::map<std::pair<Key, int>, std::uint32_t> loose;
    auto lip_corner = [&](const Vec3& p, const mesh::Face& face, int side, const Vec3& n) {
        if (const auto it = refined_at.find(key_of(p)); it != refined_at.end())
            return copies_at[it->second].size() > 1 ? copy_behind(e, copies_at[it->second], n)
                                                    : copies_at[it->second].front();
        Index node = kNone;
        if (const auto it = side_node[side].find(key_of(p)); it != side_node[side].end())
            node = it->second;
        const Vec3 towards = mesh.cell_centroid(face.owner);
        const double reach = (towards - p).norm();
        // Into the face's cell on its own side, through the cut plane on the other side.
        const Vec3 probe = side == 0 ? Vec3(p + kProbeStep * (towards - p))
                                     : Vec3(p + kProbeStep * reach * n.normalized());
        std::uint32_t* slot = nullptr;
        bool made = false;
        if (node != kNone) {
            const auto r = state.node_vertex.emplace(node, 0u);
            slot = &r.first->second;
            made = r.second;
        } else {
            // Past the mesh, on the crack front's line: the material has not parted, one
            // vertex for both sides (as the front's nodes are).
            const int key_side = surface.front.count(key_of(p)) ? 0 : side;
            const auto r = loose.emplace(std::make_pair(key_of(p), key_side), 0u);
            slot = &r.first->second;
            made = r.second;
        }
        if (made) {
            *slot = add_vertex(e, p, probe);
            to_embed.insert(*slot);
            ++report.vertices_added;
        }
        return *slot;
    };
    const detail::TriangleSet& rc = refined.cut;
    for (std::size_t t = 0; t < rc.triangles.size(); ++t) {
        const auto& tri = rc.triangles[t];
        const Vec3 &a = rc.points[tri[0]], &b = rc.points[tri[1]], &c = rc.points[tri[2]];
        const Vec3 nt_ = (b - a).cross(c - a);
        if (!(nt_.norm() > 0))
            continue;
        const Vec3 centroid = (a + b + c) / 3.0;
        if (!inside(centroid))
            continue;
        const std::size_t i = cut_face[rc.origin[t]];
        const mesh::Face& face = mesh.faces[std::size_t(faces[i])];
        std::array<std::array<std::uint32_t, 3>, 2> out {};
        for (int side = 0; side < 2; ++side) {
            // Outward: along the kept face's normal on its side, against it on the other.
            const Vec3 n = side == 0 ? normal[i] : Vec3(-normal[i]);
            for (int k = 0; k < 3; ++k)
                out[side][std::size_t(k)]
                    = lip_corner(rc.points[tri[std::size_t(k)]], face, side, n);
            if (nt_.dot(n) < 0)
                std::swap(out[side][1], out[side][2]);
        }
        // All three corners on the crack front (nodes both sides share): the two lips are one
        // triangle back to back and move alike; neither is made.
        std::array<std::uint32_t, 3> first = out[0], second = out[1];
        std::sort(first.begin(), first.end());
        std::sort(second.begin(), second.end());
        if (first == second)
            continue;
        for (const auto& lip : out) {
            e.triangles.insert(e.triangles.end(), lip.begin(), lip.end());
            e.lip.push_back(1);
            ++report.lip_triangles_added;
        }
    }

    // 6. Embedding.
    for (std::size_t v = vertices_before; v < e.rest.size(); ++v)
        to_embed.insert(std::uint32_t(v));
    reembed_list.assign(to_embed.begin(), to_embed.end());
    reembed(e, mesh, reembed_list, poly);
    report.reembedded = reembed_list.size();
    report.total_ms = watch.ms();
    return report;
}

} // namespace polycut::embed

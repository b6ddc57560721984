// Mesh validation (issue 2 item 3): topology first (face table, cell closedness, shape tags), then
// geometry (planarity, volume, convexity), then nodes (duplicates, unused), then the boundary
// surface. Each check is linear in the mesh size; per-cell buffers are reused.
#include "polycut/mesh/validate.hpp"

#include "polycut/common/error.hpp"
#include "polycut/geometry/polygon.hpp"
#include "polycut/geometry/polyhedron.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <sstream>
#include <tuple>
#include <unordered_map>

namespace polycut::mesh {
namespace {
using Kind = ValidationIssue::Kind;

std::string fmt(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}

struct Issues {
    std::vector<ValidationIssue> list;
    void add(Kind kind, Index cell, Index face, Index node, std::string message) {
        list.push_back({ kind, cell, face, node, kNone, std::move(message) });
    }
};

std::uint64_t edge_key(Index a, Index b) {
    const auto lo = std::uint32_t(std::min(a, b));
    const auto hi = std::uint32_t(std::max(a, b));
    return (std::uint64_t(lo) << 32) | hi;
}

/// True when `loop` equals `ref` up to a cyclic rotation.
template <class Ref> bool same_cycle(const std::vector<Index>& loop, const Ref& ref) {
    const std::size_t k = loop.size();
    if (k != ref.size())
        return false;
    for (std::size_t s = 0; s < k; ++s) {
        bool eq = true;
        for (std::size_t i = 0; i < k && eq; ++i)
            eq = loop[(s + i) % k] == ref[i];
        if (eq)
            return true;
    }
    return false;
}

/// Checks that a Tet/Hex cell's VTK node order matches its faces, loop orientation included.
/// Returns an empty string when it does.
template <std::size_t F, std::size_t K>
std::string check_template(const Cell& cell, const std::vector<std::vector<Index>>& loops,
    const std::array<std::array<int, K>, F>& faces, std::size_t num_nodes, const char* name) {
    if (cell.nodes.size() != num_nodes || loops.size() != F)
        return std::string("tagged ") + name + " but has " + std::to_string(cell.nodes.size())
            + " nodes and " + std::to_string(loops.size()) + " faces";
    for (const auto& f : faces) {
        std::array<Index, K> ref {};
        for (std::size_t i = 0; i < K; ++i)
            ref[i] = cell.nodes[std::size_t(f[i])];
        const bool found = std::any_of(
            loops.begin(), loops.end(), [&](const auto& loop) { return same_cycle(loop, ref); });
        if (!found)
            return std::string("tagged ") + name
                + " but its node order does not give its outward faces (VTK order expected)";
    }
    return {};
}

/// Per-cell topological and geometric checks. `loops` holds the cell's outward loops.
class CellChecker {
public:
    CellChecker(const Mesh& mesh, const ValidationOptions& options, Issues& issues)
        : m_mesh(mesh)
        , m_options(options)
        , m_issues(issues) { }

    void check(Index c) {
        const Cell& cell = m_mesh.cells[std::size_t(c)];
        m_loops.resize(cell.faces.size());
        for (std::size_t i = 0; i < cell.faces.size(); ++i) {
            const Face& face = m_mesh.faces[std::size_t(cell.faces[i])];
            m_loops[i].assign(face.nodes.begin(), face.nodes.end());
            if (face.owner != c)
                std::reverse(m_loops[i].begin(), m_loops[i].end());
        }
        geometry::Aabb box;
        for (Index n : cell.nodes)
            box.extend(m_mesh.rest[std::size_t(n)]);
        const double size = box.diagonal();

        if (cell.shape != CellShape::Polyhedron) {
            const std::string problem = cell.shape == CellShape::Tet
                ? check_template(cell, m_loops, kTetFaces, 4, "Tet")
                : check_template(cell, m_loops, kHexFaces, 8, "Hex");
            if (!problem.empty())
                m_issues.add(Kind::BadShape, c, kNone, kNone, problem);
        }
        for (Index f : cell.faces)
            if (m_mesh.faces[std::size_t(f)].owner == c)
                check_planarity(c, f, size);
        if (!check_closed(c))
            return;
        const double volume = geometry::polyhedron_volume(m_mesh.rest, m_loops);
        const double eps = 1e-12 * size * size * size;
        if (volume < -eps) {
            m_issues.add(Kind::InvertedCell, c, cell.faces.front(), kNone,
                "rest volume " + fmt(volume) + " m^3");
            return;
        }
        if (std::abs(volume) <= eps || volume <= m_options.min_volume) {
            m_issues.add(Kind::ZeroVolumeCell, c, cell.faces.front(), kNone,
                "rest volume " + fmt(volume) + " m^3 (size " + fmt(size) + " m, min_volume "
                    + fmt(m_options.min_volume) + " m^3)");
            return;
        }
        if (m_options.require_convex
            && !geometry::polyhedron_is_convex(
                m_mesh.rest, m_loops, 4 * m_options.planarity_tol + 1e-12))
            m_issues.add(Kind::NonConvexCell, c, cell.faces.front(), kNone, "cell is not convex");
    }

private:
    void check_planarity(Index c, Index f, double size) {
        const Face& face = m_mesh.faces[std::size_t(f)];
        m_points.clear();
        for (Index n : face.nodes)
            m_points.push_back(m_mesh.rest[std::size_t(n)]);
        const double err = geometry::planarity_error(m_points);
        if (err > m_options.planarity_tol * size)
            m_issues.add(Kind::NonPlanarFace, c, f, kNone,
                "a node is " + fmt(err) + " m off its plane (cell size " + fmt(size)
                    + " m, tolerance " + fmt(m_options.planarity_tol) + ")");
    }

    /// Every directed edge (a, b) of the outward loops must appear once, and (b, a) once.
    bool check_closed(Index c) {
        const Cell& cell = m_mesh.cells[std::size_t(c)];
        if (cell.faces.size() < 4) {
            m_issues.add(Kind::OpenCell, c, cell.faces.empty() ? kNone : cell.faces.front(), kNone,
                "only " + std::to_string(cell.faces.size()) + " faces");
            return false;
        }
        m_edges.clear();
        for (std::size_t i = 0; i < m_loops.size(); ++i) {
            const auto& loop = m_loops[i];
            for (std::size_t k = 0; k < loop.size(); ++k)
                m_edges.push_back({ loop[k], loop[(k + 1) % loop.size()], Index(i) });
        }
        std::sort(m_edges.begin(), m_edges.end());
        auto count = [&](Index a, Index b) {
            const DirectedEdge lo { a, b, std::numeric_limits<Index>::min() };
            const DirectedEdge hi { a, b, std::numeric_limits<Index>::max() };
            return std::upper_bound(m_edges.begin(), m_edges.end(), hi)
                - std::lower_bound(m_edges.begin(), m_edges.end(), lo);
        };
        for (const DirectedEdge& e : m_edges) {
            const auto same = count(e.a, e.b);
            const auto opposite = count(e.b, e.a);
            if (same != 1 || opposite != 1) {
                const Index f = cell.faces[std::size_t(e.local_face)];
                std::string why = same > 1 ? "is used twice in the same direction (flipped face?)"
                    : opposite == 0 ? "is not shared with another face of the cell (missing face?)"
                                    : "is shared by more than two faces of the cell";
                m_issues.add(Kind::OpenCell, c, f, kNone,
                    "edge (" + std::to_string(e.a) + ", " + std::to_string(e.b) + ") " + why);
                return false;
            }
        }
        return true;
    }

    struct DirectedEdge {
        Index a, b, local_face;
        bool operator<(const DirectedEdge& o) const {
            return std::tie(a, b, local_face) < std::tie(o.a, o.b, o.local_face);
        }
    };

    const Mesh& m_mesh;
    const ValidationOptions& m_options;
    Issues& m_issues;
    std::vector<std::vector<Index>> m_loops;
    std::vector<Vec3> m_points;
    std::vector<DirectedEdge> m_edges;
};

/// Face table checks. Returns per-face ok flags (ids in range, >= 3 distinct nodes).
std::vector<char> check_faces(const Mesh& mesh, Issues& issues) {
    const Index N = mesh.num_nodes(), C = mesh.num_cells();
    std::vector<char> ok(mesh.faces.size(), 1);
    std::vector<Index> sorted;
    for (Index f = 0; f < mesh.num_faces(); ++f) {
        const Face& face = mesh.faces[std::size_t(f)];
        const Index owner = face.owner >= 0 && face.owner < C ? face.owner : kNone;
        auto bad = [&](const std::string& what) {
            issues.add(Kind::BadAdjacency, owner, f, kNone, what);
            ok[std::size_t(f)] = 0;
        };
        if (face.nodes.size() < 3) {
            bad("face has " + std::to_string(face.nodes.size()) + " nodes (at least 3 needed)");
            continue;
        }
        const auto out = std::find_if(
            face.nodes.begin(), face.nodes.end(), [&](Index n) { return n < 0 || n >= N; });
        if (out != face.nodes.end()) {
            bad("face node " + std::to_string(*out) + " out of range [0, " + std::to_string(N)
                + ")");
            continue;
        }
        sorted.assign(face.nodes.begin(), face.nodes.end());
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
            bad("face repeats a node");
            continue;
        }
        if (owner == kNone) {
            bad("face owner " + std::to_string(face.owner) + " out of range [0, "
                + std::to_string(C) + ")");
            continue;
        }
        if (face.neighbour != kNone && (face.neighbour < 0 || face.neighbour >= C)) {
            bad("face neighbour " + std::to_string(face.neighbour) + " out of range");
            continue;
        }
        if (face.neighbour == face.owner) {
            bad("face has the same owner and neighbour");
            continue;
        }
        if (face.boundary() == (face.tag == FaceTag::Interior))
            bad(face.boundary() ? "boundary face tagged Interior"
                                : "interior face tagged Skin/Cut");
    }
    return ok;
}

/// Cell -> face references: every face a cell lists must name it as owner or neighbour, and
/// the owner and neighbour of every face must list it. Returns per-cell ok flags.
std::vector<char> check_cell_faces(
    const Mesh& mesh, const std::vector<char>& face_ok, Issues& issues) {
    const Index F = mesh.num_faces(), N = mesh.num_nodes();
    std::vector<char> ok(mesh.cells.size(), 1);
    std::vector<char> listed_by_owner(mesh.faces.size(), 0);
    std::vector<char> listed_by_neighbour(mesh.faces.size(), 0);
    std::vector<Index> face_nodes, cell_nodes, faces;
    for (Index c = 0; c < mesh.num_cells(); ++c) {
        const Cell& cell = mesh.cells[std::size_t(c)];
        auto bad = [&](Index f, const std::string& what) {
            issues.add(Kind::BadAdjacency, c, f, kNone, what);
            ok[std::size_t(c)] = 0;
        };
        faces.assign(cell.faces.begin(), cell.faces.end());
        std::sort(faces.begin(), faces.end());
        if (const auto dup = std::adjacent_find(faces.begin(), faces.end()); dup != faces.end()) {
            bad(*dup, "cell lists face " + std::to_string(*dup) + " twice");
            continue;
        }
        face_nodes.clear();
        for (Index f : cell.faces) {
            if (f < 0 || f >= F) {
                bad(kNone, "face id " + std::to_string(f) + " out of range");
                continue;
            }
            const Face& face = mesh.faces[std::size_t(f)];
            if (face.owner == c)
                listed_by_owner[std::size_t(f)] = 1;
            else if (face.neighbour == c)
                listed_by_neighbour[std::size_t(f)] = 1;
            else
                bad(f,
                    "cell lists a face whose owner (" + std::to_string(face.owner)
                        + ") and neighbour (" + std::to_string(face.neighbour)
                        + ") are other cells");
            if (!face_ok[std::size_t(f)])
                ok[std::size_t(c)] = 0;
            face_nodes.insert(face_nodes.end(), face.nodes.begin(), face.nodes.end());
        }
        if (!ok[std::size_t(c)])
            continue;
        std::sort(face_nodes.begin(), face_nodes.end());
        face_nodes.erase(std::unique(face_nodes.begin(), face_nodes.end()), face_nodes.end());
        cell_nodes.assign(cell.nodes.begin(), cell.nodes.end());
        std::sort(cell_nodes.begin(), cell_nodes.end());
        if (std::any_of(
                cell_nodes.begin(), cell_nodes.end(), [&](Index n) { return n < 0 || n >= N; })
            || cell_nodes != face_nodes)
            bad(kNone, "cell nodes are not the nodes of its faces");
    }
    for (Index f = 0; f < F; ++f) {
        const Face& face = mesh.faces[std::size_t(f)];
        if (!face_ok[std::size_t(f)])
            continue;
        if (!listed_by_owner[std::size_t(f)]) {
            issues.add(Kind::BadAdjacency, face.owner, f, kNone,
                "owner cell " + std::to_string(face.owner) + " does not list the face");
            ok[std::size_t(face.owner)] = 0;
        }
        if (face.neighbour != kNone && !listed_by_neighbour[std::size_t(f)]) {
            issues.add(Kind::BadAdjacency, face.neighbour, f, kNone,
                "neighbour cell " + std::to_string(face.neighbour) + " does not list the face");
            ok[std::size_t(face.neighbour)] = 0;
        }
    }
    return ok;
}

/// Coincident nodes through a sorted grid of cell size >= tol: each node looks in the 27
/// bins around its own. O(N log N).
void check_duplicates(const Mesh& mesh, const ValidationOptions& options,
    const std::vector<char>& finite, const std::vector<Index>& first_cell, Issues& issues) {
    const Index N = mesh.num_nodes();
    geometry::Aabb box;
    for (Index n = 0; n < N; ++n)
        if (finite[std::size_t(n)])
            box.extend(mesh.rest[std::size_t(n)]);
    if (box.empty())
        return;
    const double tol = options.duplicate_tol * box.diagonal();
    const double bin = std::max({ tol, 1e-9 * box.diagonal(), 1e-300 });
    std::vector<char> on_cut(std::size_t(N), 0), used(std::size_t(N), 0);
    for (const Face& f : mesh.faces)
        for (Index n : f.nodes)
            if (n >= 0 && n < N) {
                used[std::size_t(n)] = 1;
                if (f.tag == FaceTag::Cut)
                    on_cut[std::size_t(n)] = 1;
            }
    using Key = std::array<std::int64_t, 3>;
    auto key_of = [&](const Vec3& p) {
        const Vec3 q = (p - box.lo) / bin;
        return Key { std::int64_t(std::floor(q.x())), std::int64_t(std::floor(q.y())),
            std::int64_t(std::floor(q.z())) };
    };
    std::vector<std::pair<Key, Index>> keyed;
    keyed.reserve(std::size_t(N));
    // Nodes no face uses (left behind by cuts that coarsened them away) cannot pinch anything.
    for (Index n = 0; n < N; ++n)
        if (finite[std::size_t(n)] && used[std::size_t(n)])
            keyed.push_back({ key_of(mesh.rest[std::size_t(n)]), n });
    std::sort(keyed.begin(), keyed.end());
    for (const auto& [key, n] : keyed) {
        const Vec3& p = mesh.rest[std::size_t(n)];
        // Neighbour bins only where p is within tol of the bin's side (bins are >= tol wide).
        std::array<int, 3> from {}, to {};
        for (int a = 0; a < 3; ++a) {
            const double offset = (p[a] - box.lo[a]) - double(key[std::size_t(a)]) * bin;
            from[std::size_t(a)] = offset <= tol ? -1 : 0;
            to[std::size_t(a)] = bin - offset <= tol ? 1 : 0;
        }
        Index twin = kNone;
        for (int dz = from[2]; dz <= to[2] && twin == kNone; ++dz)
            for (int dy = from[1]; dy <= to[1] && twin == kNone; ++dy)
                for (int dx = from[0]; dx <= to[0] && twin == kNone; ++dx) {
                    const Key k { key[0] + dx, key[1] + dy, key[2] + dz };
                    auto it = std::lower_bound(keyed.begin(), keyed.end(),
                        std::pair<Key, Index> { k, std::numeric_limits<Index>::min() });
                    for (; it != keyed.end() && it->first == k; ++it) {
                        const Index m = it->second;
                        if (m >= n || (on_cut[std::size_t(m)] && on_cut[std::size_t(n)]))
                            continue;
                        if ((mesh.rest[std::size_t(m)] - p).norm() <= tol) {
                            twin = m;
                            break;
                        }
                    }
                }
        if (twin != kNone) {
            issues.add(Kind::DuplicateNodes, first_cell[std::size_t(n)], kNone, n,
                "node " + std::to_string(n) + " coincides with node " + std::to_string(twin)
                    + " (distance <= " + fmt(tol) + " m)");
            issues.list.back().other = twin;
        }
    }
}

struct EdgeRecord {
    Index count = 0;
    Index sum = 0; ///< +1 per use as (lo, hi), -1 per use as (hi, lo)
    Index face = kNone; ///< first boundary face (local number) using the edge
};

struct BoundaryEdges {
    std::vector<Index> faces; ///< global ids of the boundary faces
    std::unordered_map<std::uint64_t, EdgeRecord> edges;
    std::vector<Index> parent; ///< union-find over local boundary faces

    Index find(Index a) {
        while (parent[std::size_t(a)] != a) {
            parent[std::size_t(a)] = parent[std::size_t(parent[std::size_t(a)])];
            a = parent[std::size_t(a)];
        }
        return a;
    }
};

/// Hashes the edges of all boundary faces with valid node ids and joins faces sharing edges.
BoundaryEdges collect_boundary_edges(const Mesh& mesh) {
    BoundaryEdges b;
    std::size_t corners = 0;
    for (Index f = 0; f < mesh.num_faces(); ++f) {
        const Face& face = mesh.faces[std::size_t(f)];
        if (!face.boundary() || face.nodes.size() < 3)
            continue;
        if (std::any_of(face.nodes.begin(), face.nodes.end(),
                [&](Index n) { return n < 0 || n >= mesh.num_nodes(); }))
            continue;
        b.faces.push_back(f);
        corners += face.nodes.size();
    }
    b.edges.reserve(corners / 2 + 1);
    b.parent.resize(b.faces.size());
    std::iota(b.parent.begin(), b.parent.end(), 0);
    for (Index i = 0; i < Index(b.faces.size()); ++i) {
        const auto& loop = mesh.faces[std::size_t(b.faces[std::size_t(i)])].nodes;
        for (std::size_t k = 0; k < loop.size(); ++k) {
            const Index u = loop[k], v = loop[(k + 1) % loop.size()];
            EdgeRecord& e = b.edges[edge_key(u, v)];
            e.count += 1;
            e.sum += u < v ? 1 : -1;
            if (e.face == kNone)
                e.face = i;
            else
                b.parent[std::size_t(b.find(i))] = b.find(e.face);
        }
    }
    return b;
}

bool edge_ok(const EdgeRecord& e) {
    return e.count == 2 && e.sum == 0;
}
} // namespace

const char* kind_name(ValidationIssue::Kind kind) {
    switch (kind) {
    case Kind::NonFinite:
        return "non-finite position";
    case Kind::BadAdjacency:
        return "bad adjacency";
    case Kind::BadShape:
        return "bad shape tag";
    case Kind::OpenCell:
        return "open cell";
    case Kind::NonPlanarFace:
        return "non-planar face";
    case Kind::InvertedCell:
        return "inverted cell";
    case Kind::ZeroVolumeCell:
        return "zero-volume cell";
    case Kind::NonConvexCell:
        return "non-convex cell";
    case Kind::DuplicateNodes:
        return "duplicate nodes";
    case Kind::UnusedNode:
        return "unused node";
    case Kind::NonManifoldBoundary:
        return "non-manifold boundary";
    }
    return "unknown";
}

std::vector<ValidationIssue> check_mesh(const Mesh& mesh, const ValidationOptions& options) {
    Issues issues;
    const Index N = mesh.num_nodes();

    // Nodes: finite positions; first cell using each node (for error locations).
    std::vector<char> finite(std::size_t(N), 1);
    std::vector<Index> first_cell(std::size_t(N), kNone);
    for (Index c = mesh.num_cells() - 1; c >= 0; --c)
        for (Index n : mesh.cells[std::size_t(c)].nodes)
            if (n >= 0 && n < N)
                first_cell[std::size_t(n)] = c;
    for (Index n = 0; n < N; ++n)
        if (!mesh.rest[std::size_t(n)].allFinite()) {
            finite[std::size_t(n)] = 0;
            issues.add(Kind::NonFinite, first_cell[std::size_t(n)], kNone, n,
                "node " + std::to_string(n) + " has a non-finite rest position");
        }

    // Topology of the face table, then each cell's geometry.
    const auto face_ok = check_faces(mesh, issues);
    const auto cell_ok = check_cell_faces(mesh, face_ok, issues);
    CellChecker checker(mesh, options, issues);
    for (Index c = 0; c < mesh.num_cells(); ++c) {
        if (!cell_ok[std::size_t(c)])
            continue;
        const auto& nodes = mesh.cells[std::size_t(c)].nodes;
        if (std::all_of(
                nodes.begin(), nodes.end(), [&](Index n) { return finite[std::size_t(n)]; }))
            checker.check(c);
    }

    // Nodes: coincident and unused.
    if (options.check_duplicates)
        check_duplicates(mesh, options, finite, first_cell, issues);
    if (!options.allow_unused_nodes)
        for (Index n = 0; n < N; ++n)
            if (first_cell[std::size_t(n)] == kNone)
                issues.add(Kind::UnusedNode, kNone, kNone, n,
                    "node " + std::to_string(n) + " is not used by any cell");

    // Boundary surface: each bad edge once, in boundary-face order.
    if (options.check_boundary) {
        BoundaryEdges b = collect_boundary_edges(mesh);
        for (const Index f : b.faces) {
            const auto& loop = mesh.faces[std::size_t(f)].nodes;
            for (std::size_t k = 0; k < loop.size(); ++k) {
                const Index u = loop[k], v = loop[(k + 1) % loop.size()];
                auto it = b.edges.find(edge_key(u, v));
                if (it == b.edges.end() || edge_ok(it->second) || it->second.count == 0)
                    continue;
                const EdgeRecord e = it->second;
                it->second.count = 0; // report once
                const std::string what = e.count == 1 ? "is used by one boundary face (hole)"
                    : e.count > 2 ? "is shared by " + std::to_string(e.count) + " boundary faces"
                                  : "is used twice in the same direction (misoriented faces)";
                issues.add(Kind::NonManifoldBoundary, mesh.faces[std::size_t(f)].owner, f, kNone,
                    "boundary edge (" + std::to_string(u) + ", " + std::to_string(v) + ") " + what);
            }
        }
    }
    return std::move(issues.list);
}

void validate(const Mesh& mesh, const ValidationOptions& options) {
    const auto issues = check_mesh(mesh, options);
    if (issues.empty())
        return;
    const ValidationIssue& first = issues.front();
    std::string what = std::string(kind_name(first.kind)) + ": " + first.message;
    if (first.node != kNone && what.find("node") == std::string::npos)
        what += " (node " + std::to_string(first.node) + ")";
    if (issues.size() > 1)
        what += " [" + std::to_string(issues.size() - 1) + " more issue"
            + (issues.size() > 2 ? "s" : "") + "]";
    throw MeshError(first.cell, first.face, what);
}

SurfaceCheck check_boundary_surface(const Mesh& mesh) {
    BoundaryEdges b = collect_boundary_edges(mesh);
    SurfaceCheck out;
    out.faces = Index(b.faces.size());
    Index bad_local = kNone;
    for (const auto& [key, e] : b.edges) {
        if (edge_ok(e))
            continue;
        if (e.count == 1)
            ++out.boundary_edges;
        else if (e.count > 2)
            ++out.nonmanifold_edges;
        if (e.sum != 0 && e.count == 2)
            ++out.misoriented_edges;
        if (bad_local == kNone || e.face < bad_local)
            bad_local = e.face;
    }
    out.closed = out.boundary_edges == 0 && out.nonmanifold_edges == 0;
    out.oriented = out.misoriented_edges == 0;
    out.first_bad_face = bad_local == kNone ? kNone : b.faces[std::size_t(bad_local)];
    for (Index i = 0; i < out.faces; ++i)
        out.components += b.find(i) == i ? 1 : 0;
    return out;
}

} // namespace polycut::mesh

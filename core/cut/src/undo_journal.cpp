// cut::detail::UndoJournal: the mirror of the mesh before the last cut (see undo_journal.hpp).
#include "undo_journal.hpp"

#include "checks.hpp"

#include <algorithm>
#include <cstdlib>
#include <numeric>
#include <stdexcept>
#include <string>

namespace polycut::cut::detail {
namespace {
/// to = from, element by element: each element's own vectors keep their capacity, so a whole
/// copy of a mesh into one of about its size allocates nothing (a vector's operator= copies
/// into fresh elements whenever it must grow, and every cut grows the mesh).
template <class T> void assign_elementwise(std::vector<T>& to, const std::vector<T>& from) {
    if (to.capacity() < from.size())
        to.reserve(from.size() + from.size() / 8 + 64);
    to.resize(from.size());
    for (std::size_t i = 0; i < from.size(); ++i)
        to[i] = from[i];
}

void assign_elementwise(mesh::Mesh& to, const mesh::Mesh& from) {
    assign_elementwise(to.rest, from.rest);
    assign_elementwise(to.faces, from.faces);
    assign_elementwise(to.cells, from.cells);
}

template <class T> void grow_from(std::vector<T>& to, const std::vector<T>& from, std::size_t n0) {
    if (to.capacity() < from.size())
        to.reserve(from.size() + from.size() / 8 + 64);
    to.resize(from.size());
    for (std::size_t i = std::min(n0, from.size()); i < from.size(); ++i)
        to[i] = from[i];
}
} // namespace

void Mirror::record(const CutReport& r) {
    if (!r.topology_changed && r.moved_nodes.empty())
        return;
    m_pending = true;
    // Renumbering calls: ids in the report are after a compaction of cells, faces or nodes, so
    // every later element may have moved (face parents too). A compaction of merged cut faces
    // alone (the splitting cutter's every call) carries its face map: the copy's faces move
    // along it at the next sync, O(faces) moves and integer rewrites instead of a deep copy of
    // the whole mesh (~4.5 ms per tick on the 5k organ).
    const bool faces_only = r.faces_renumbered && !r.face_map.empty()
        && r.face_map.size() == std::size_t(r.faces_before) && r.cell_map.empty()
        && r.node_map.empty() && r.slivers_merged == 0 && r.removed_cells.empty()
        && r.removed_nodes.empty();
    if (faces_only && !m_whole_pending) {
        if (m_face_map.empty()) {
            m_face_map.resize(m_mesh.faces.size());
            std::iota(m_face_map.begin(), m_face_map.end(), Index(0));
        }
        for (Index& f : m_face_map)
            if (f != kNone)
                f = std::size_t(f) < r.face_map.size() ? r.face_map[std::size_t(f)] : kNone;
    } else if (r.faces_renumbered || !r.cell_map.empty() || !r.node_map.empty()
        || r.slivers_merged > 0 || r.cut_faces_merged > 0 || !r.removed_cells.empty()
        || !r.removed_nodes.empty()) {
        m_whole_pending = true; // (a mesh that shrank is copied whole by sync() too)
    }
    if (m_whole_pending)
        return;
    m_cells.insert(m_cells.end(), r.changed_cells.begin(), r.changed_cells.end());
    for (const auto& [node, old_rest] : r.moved_nodes)
        m_nodes.push_back(node);
}

bool Mirror::sync(const mesh::Mesh& mesh) {
    // Lists from calls later undone are harmless: copying an element that did not change (or
    // changed back) copies the value it has.
    const bool moved_faces = !m_face_map.empty();
    const bool whole = m_whole_pending || (!moved_faces && mesh.faces.size() < m_mesh.faces.size())
        || mesh.cells.size() < m_mesh.cells.size() || mesh.rest.size() < m_mesh.rest.size();
    if (whole) {
        assign_elementwise(m_mesh, mesh);
    } else {
        std::size_t f0 = m_mesh.faces.size();
        if (moved_faces) {
            // Compactions keep the order, so a face only moves down: in place, ascending. The
            // places no old face lands on hold faces the calls appended (copied below with the
            // faces of the changed cells); parents follow the mesh's (a merged-away parent was
            // replaced by its survivor).
            std::vector<char> landed(mesh.faces.size(), 0);
            for (std::size_t f = 0; f < f0; ++f) {
                const Index to = m_face_map[f];
                if (to == kNone || std::size_t(to) >= mesh.faces.size())
                    continue;
                if (std::size_t(to) != f)
                    m_mesh.faces[std::size_t(to)] = std::move(m_mesh.faces[f]);
                landed[std::size_t(to)] = 1;
            }
            if (m_mesh.faces.capacity() < mesh.faces.size())
                m_mesh.faces.reserve(mesh.faces.size() + mesh.faces.size() / 8 + 64);
            m_mesh.faces.resize(mesh.faces.size());
            for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
                if (!landed[f])
                    m_mesh.faces[f] = mesh.faces[f];
                else
                    m_mesh.faces[f].parent = mesh.faces[f].parent;
            }
            for (mesh::Cell& cell : m_mesh.cells)
                for (Index& f : cell.faces)
                    if (std::size_t(f) < m_face_map.size())
                        f = m_face_map[std::size_t(f)];
            f0 = mesh.faces.size(); // every face is in place now; changed cells' ones below
        }
        grow_from(m_mesh.rest, mesh.rest, m_mesh.rest.size());
        grow_from(m_mesh.faces, mesh.faces, f0);
        grow_from(m_mesh.cells, mesh.cells, m_mesh.cells.size());
        for (Index n : m_nodes)
            if (n >= 0 && std::size_t(n) < mesh.rest.size())
                m_mesh.rest[std::size_t(n)] = mesh.rest[std::size_t(n)];
        // A face a cut rewrites (split, a node inserted on one of its edges, a new owner or
        // neighbour, a new tag) belongs to a cell the cut changed on both of its sides.
        for (Index c : m_cells) {
            if (c < 0 || std::size_t(c) >= mesh.cells.size())
                continue;
            const mesh::Cell& cell = mesh.cells[std::size_t(c)];
            m_mesh.cells[std::size_t(c)] = cell;
            for (Index f : cell.faces)
                if (std::size_t(f) < f0)
                    m_mesh.faces[std::size_t(f)] = mesh.faces[std::size_t(f)];
        }
    }
    m_pending = m_whole_pending = false;
    m_cells.clear();
    m_nodes.clear();
    m_face_map.clear();
    return whole;
}

void Mirror::assign(const mesh::Mesh& mesh) {
    assign_elementwise(m_mesh, mesh);
    clear();
}

void Mirror::clear() {
    m_pending = m_whole_pending = false;
    m_cells.clear();
    m_nodes.clear();
    m_face_map.clear();
}

UndoJournal::UndoJournal(const mesh::Mesh& mesh)
    : m_call(mesh)
    , m_accepted(mesh)
    , m_check(incremental_checks()) { }

void UndoJournal::record(const CutReport& r) {
    m_call.record(r);
    m_accepted.record(r);
}

void UndoJournal::sync(Mirror& mirror, const mesh::Mesh& mesh) {
    if (!mirror.pending())
        return;
    const bool moves = mirror.moves_faces();
    if (mirror.sync(mesh))
        ++m_whole;
    else if (moves)
        ++m_face_moves;
    if (m_check)
        require_equal_meshes(mirror.mesh(), mesh);
}

void UndoJournal::commit(const mesh::Mesh& mesh) {
    if (m_calls++ > 0)
        sync(m_call, mesh); // a second call since accept(): its undo needs the mesh before it
}

void UndoJournal::accept(const mesh::Mesh& mesh) {
    sync(m_accepted, mesh);
    m_calls = 0;
}

void UndoJournal::undo(mesh::Mesh& mesh) {
    if (m_calls <= 1) {
        // The first call since accept() failed: the accepted mesh is the one before it.
        assign_elementwise(mesh, m_accepted.mesh());
        m_accepted.clear();
        m_call.invalidate();
    } else {
        assign_elementwise(mesh, m_call.mesh());
        m_call.clear();
    }
}

void UndoJournal::undo_all(mesh::Mesh& mesh) {
    assign_elementwise(mesh, m_accepted.mesh());
    m_accepted.clear();
    m_call.invalidate();
    m_calls = 0;
}

void require_equal_meshes(const mesh::Mesh& a, const mesh::Mesh& b) {
    auto fail = [](const std::string& what) {
        throw std::logic_error("undo journal: the mirror differs from the mesh at " + what);
    };
    if (a.rest.size() != b.rest.size())
        fail("the node count");
    for (std::size_t i = 0; i < a.rest.size(); ++i)
        if (a.rest[i] != b.rest[i])
            fail("node " + std::to_string(i));
    if (a.faces.size() != b.faces.size())
        fail("the face count");
    for (std::size_t f = 0; f < a.faces.size(); ++f) {
        const mesh::Face &x = a.faces[f], &y = b.faces[f];
        if (x.nodes != y.nodes || x.owner != y.owner || x.neighbour != y.neighbour || x.tag != y.tag
            || x.parent != y.parent)
            fail("face " + std::to_string(f));
    }
    if (a.cells.size() != b.cells.size())
        fail("the cell count");
    for (std::size_t c = 0; c < a.cells.size(); ++c) {
        const mesh::Cell &x = a.cells[c], &y = b.cells[c];
        if (x.nodes != y.nodes || x.faces != y.faces || x.shape != y.shape || x.parent != y.parent)
            fail("cell " + std::to_string(c));
    }
}

} // namespace polycut::cut::detail

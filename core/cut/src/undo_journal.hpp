// The undo of a cut (issue 12 item 5): a mirror of the mesh as it was before the last call that
// changed it, kept up to date from the calls' reports instead of copying the mesh before each
// cut. A call's report names what it changed (changed and new cells, new and moved nodes);
// bringing the mirror up to date copies those cells, their faces and those nodes, so a cut costs
// what it touched. Only a call that renumbered (sliver merges, merged cut faces, the snap
// cutter's compaction) is mirrored by a whole copy, and only an undo copies the mirror back.
#pragma once

#include "polycut/cut/cut_report.hpp"
#include "polycut/mesh/mesh.hpp"

#include <cstdint>
#include <vector>

namespace polycut::cut::detail {

/// One copy of the mesh at some earlier moment, and what the calls since then changed.
class Mirror {
public:
    explicit Mirror(const mesh::Mesh& mesh)
        : m_mesh(mesh) { }
    /// Notes what a call changed (its report).
    void record(const CutReport& report);
    /// Brings the copy up to `mesh` from what was recorded; returns whether it copied it whole.
    bool sync(const mesh::Mesh& mesh);
    /// The copy becomes `mesh` exactly (a whole copy).
    void assign(const mesh::Mesh& mesh);
    /// The copy may differ anywhere: the next sync copies it whole.
    void invalidate() { m_pending = m_whole_pending = true; }
    /// The copy equals the mesh (it was just copied from it).
    void clear();
    const mesh::Mesh& mesh() const { return m_mesh; }
    bool pending() const { return m_pending; }
    /// The next sync moves the copy's faces along recorded compactions (not a whole copy).
    bool moves_faces() const { return !m_face_map.empty() && !m_whole_pending; }

private:
    mesh::Mesh m_mesh;
    bool m_pending = false;
    bool m_whole_pending = false; ///< a recorded call renumbered: copy everything
    /// The recorded calls compacted faces only (CutReport::face_map): the copy's face id ->
    /// the mesh's (kNone: gone), composed over the calls; empty: ids unchanged.
    std::vector<Index> m_face_map;
    std::vector<Index> m_cells; ///< changed cells (ids after the calls)
    std::vector<Index> m_nodes; ///< existing nodes the calls moved
};

/// Two mirrors: the mesh at the last accept() (undo_all() of every call since, when the step
/// after them failed) and the mesh before the last call (undo() of a call that failed). The
/// first call after an accept() starts from the accepted mesh, so the last-call mirror is only
/// brought up to date when a second call comes before the next accept(): one sync per tick of a
/// stroke, not two.
class UndoJournal {
public:
    /// Mirrors `mesh` (two whole copies, when the pipeline is made).
    explicit UndoJournal(const mesh::Mesh& mesh);

    /// Notes what a call changed (its report).
    void record(const CutReport& report);
    /// At the start of a call: the previous call is kept, the last-call mirror takes it.
    /// With checks on (env POLYCUT_CHECK_UNDO=1, or a debug build), each sync compares the
    /// whole mirror with `mesh` and throws std::logic_error naming the first difference.
    void commit(const mesh::Mesh& mesh);
    /// The calls so far are sound (the step after them succeeded): the accepted mirror takes them.
    void accept(const mesh::Mesh& mesh);
    /// Puts `mesh` back as it was before the last call (O(mesh): a failed cut only).
    void undo(mesh::Mesh& mesh);
    /// Puts `mesh` back as it was at the last accept() (O(mesh): a failed step only).
    void undo_all(mesh::Mesh& mesh);

    /// Mirror syncs that copied the whole mesh so far.
    std::uint64_t whole_copies() const { return m_whole; }
    /// Mirror syncs that moved faces along a compaction instead (Mirror::moves_faces).
    std::uint64_t face_moves() const { return m_face_moves; }

private:
    void sync(Mirror& mirror, const mesh::Mesh& mesh);
    Mirror m_call; ///< before the last call
    Mirror m_accepted; ///< at the last accept()
    int m_calls = 0; ///< calls since the last accept()
    std::uint64_t m_whole = 0;
    std::uint64_t m_face_moves = 0;
    bool m_check = false;
};

/// Throws std::logic_error naming the first field where `a` and `b` differ.
void require_equal_meshes(const mesh::Mesh& a, const mesh::Mesh& b);

} // namespace polycut::cut::detail

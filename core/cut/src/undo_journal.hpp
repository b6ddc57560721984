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

class UndoJournal {
public:
    /// Mirrors `mesh` (one whole copy, when the pipeline is made).
    explicit UndoJournal(const mesh::Mesh& mesh);

    /// Notes what a call changed in `mesh` (its report); the mirror still holds the mesh
    /// before the call until commit().
    void record(const CutReport& report, const mesh::Mesh& mesh);
    /// Brings the mirror up to `mesh` (the calls recorded since the last commit are kept).
    /// With checks on (env POLYCUT_CHECK_UNDO=1, or a debug build), compares the whole mirror
    /// with `mesh` afterwards and throws std::logic_error naming the first difference.
    void commit(const mesh::Mesh& mesh);
    /// Puts `mesh` back as it was at the last commit (O(mesh): a failed cut only).
    void undo(mesh::Mesh& mesh);
    /// Whether something was recorded since the last commit.
    bool pending() const { return m_pending; }

    /// Commits so far, and how many of them copied the whole mesh.
    std::uint64_t commits() const { return m_commits; }
    std::uint64_t whole_copies() const { return m_whole; }

private:
    mesh::Mesh m_mirror;
    bool m_pending = false;
    bool m_whole_pending = false; ///< a recorded call renumbered: copy everything
    std::vector<Index> m_cells; ///< changed cells (ids after the calls)
    std::vector<Index> m_nodes; ///< existing nodes the calls moved
    std::uint64_t m_commits = 0, m_whole = 0;
    bool m_check = false;
};

/// Throws std::logic_error naming the first field where `a` and `b` differ.
void require_equal_meshes(const mesh::Mesh& a, const mesh::Mesh& b);

} // namespace polycut::cut::detail

// Private editing model of degeneracy removal (002 sec. 3.2.3): tets as cell node lists (VTK
// order) with one label per local face (interior, skin, cut) instead of the face table, and the
// edits on them (edge/face split, edge collapse, cutting a tet free). The face table is rebuilt
// from the tets and labels afterwards (rebuild_faces), compacting cells and nodes.
#pragma once

#include "snap_state.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace polycut::cut::snap {

/// Label of a local face that is shared with another tet; other labels are mesh::FaceTag values.
inline constexpr std::uint8_t kInterior = 0;
/// Label of a tet whose labels were not loaded (Model::load_labels(cells)): it is unchanged,
/// and its faces in the face table say what its labels are.
inline constexpr std::uint8_t kUnloaded = 0xFF;

using Tet = std::array<Index, 4>;
using Labels = std::array<std::uint8_t, 4>; ///< per local face, opposite local node k

struct Model {
    State& s;
    std::vector<Labels> labels; ///< per cell

    /// What edits changed, to take them back (degeneracy removal's splits when the collapse
    /// after them is refused): the first old value of each cell and node list that existed when
    /// recording began, and the sizes then. Costs what the edits touch; a copy of the tet and
    /// adjacency arrays per attempt cost ~7 ms on the 5k organ.
    struct Journal {
        Index cells = 0; ///< cells when recording began
        Index nodes = 0; ///< nodes then
        struct OldCell {
            Index c;
            std::vector<Index> nodes;
            Labels labels;
            char changed;
        };
        std::vector<OldCell> cells_before;
        std::vector<std::pair<Index, std::vector<Index>>> node_cells_before;
        std::vector<char> cell_noted, node_noted; ///< per cell / node that existed
    };
    Journal* journal = nullptr; ///< recording when set
    /// Records cell c's node list, labels and changed flag before an edit (if recording).
    void note_cell(Index c);
    /// Records node n's list of cells before an edit (if recording).
    void note_node(Index n);
    /// Starts recording into j.
    void begin_journal(Journal& j);
    /// Takes back every edit recorded in j and stops recording.
    void undo_journal(Journal& j);

    /// Labels of every cell from the current face table.
    void load_labels();
    /// Labels of the listed cells only; the others are kUnloaded (edits must not reach them).
    void load_labels(const std::vector<Index>& cells);
    void load_label(Index c);

    Tet tet(Index c) const {
        const auto& n = at(s.m.cells, c).nodes;
        return { n[0], n[1], n[2], n[3] };
    }
    bool alive(Index c) const { return at(s.m.cells, c).nodes.size() == 4; }

    static std::array<Index, 3> key(const Tet& t, int k) {
        std::array<Index, 3> f {};
        int j = 0;
        for (int i = 0; i < 4; ++i)
            if (i != k)
                f[std::size_t(j++)] = t[std::size_t(i)];
        std::sort(f.begin(), f.end());
        return f;
    }

    double volume(const Tet& t) const {
        const Vec3& a = s.X(t[0]);
        return (s.X(t[1]) - a).dot((s.X(t[2]) - a).cross(s.X(t[3]) - a)) / 6.0;
    }
    double aspect(const Tet& t) const {
        return tet_aspect_ratio(s.X(t[0]), s.X(t[1]), s.X(t[2]), s.X(t[3]));
    }

    // 002 sec. 3.2.3: flat by aspect ratio, or with a dihedral angle close to pi (a flat tet
    // can keep an aspect ratio up to about sin(pi - large_dihedral) ~ 0.03).
    bool degenerate(const Tet& t) const {
        if (aspect(t) < s.opt.degenerate_aspect)
            return true;
        const auto ang = tet_dihedral_angles(s.X(t[0]), s.X(t[1]), s.X(t[2]), s.X(t[3]));
        return *std::max_element(ang.begin(), ang.end()) > s.opt.large_dihedral;
    }

    // Live tet other than c with the face key k, and its local face index (kNone if none).
    std::pair<Index, int> across(Index c, const std::array<Index, 3>& k) const {
        for (Index d : at(s.node_cells, k[0])) {
            if (d == c || !alive(d))
                continue;
            const Tet t = tet(d);
            for (int j = 0; j < 4; ++j)
                if (key(t, j) == k)
                    return { d, j };
        }
        return { kNone, -1 };
    }

    /// Cuts tet c free and deletes it (002 sec. 3.2.3, last resort): its interior faces become
    /// Cut faces of the tets across them. Refused (nothing changed) if an edge of c would be left
    /// with its ring of tets in two fans (a non-manifold edge no node duplication repairs) or if
    /// the rest volume budget does not cover the tet's volume.
    bool cut_free(Index c);
    /// Replaces the nodes of cell c by t (adjacency updated, cell touched).
    void set_cell(Index c, const Tet& t);
    /// Deletes cell c (its node list becomes empty; compacted by rebuild_faces).
    void kill(Index c);
    /// A compaction's move of tet `from` to id `to`: its cell (nodes, faces), labels and
    /// per-tet state (marks, flags, pre-call ids, cached volume and bounds). Callers rename the
    /// faces and adjacency that name it.
    void move_cell(Index from, Index to);
    /// Keeps the first n tets, with their labels and per-tet state.
    void resize_cells(Index n);
    /// Appends a tet with face labels l, a child of cell `parent`.
    Index add_cell(const Tet& t, const Labels& l, Index parent);
    /// Splits simplex `sigma` (an edge or a face, node ids) at Xm with interpolation weights w:
    /// every tet containing it is replaced by one child per node of sigma with that node replaced
    /// by the new node. Returns the new node.
    Index split(const std::vector<Index>& sigma, const Vec3& Xm, const Weights& w);
    /// Merges node v into node u placed at Xu. Returns false (nothing changed) if the result
    /// would be invalid: a non-positive or too flat tet, an interior face not shared by exactly
    /// two tets, a non-manifold boundary around u, or a rest volume change over the budget.
    bool collapse(Index u, Index v, const Vec3& Xu);
};

/// Interpolation weights (over pre-call nodes) of the point (1 - t) X(a) + t X(b).
Weights mix(const State& s, Index a, Index b, double t);

/// Rebuilds the face table from the tets and labels of md, compacts cells and nodes (recording
/// removed pre-call ids in the State) and re-finds pending faces by their node sets; returns the
/// node map (old -> new id, kNone if unused).
std::vector<Index> rebuild_faces(Model& md);

} // namespace polycut::cut::snap

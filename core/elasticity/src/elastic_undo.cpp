// ElasticModel's undo journal (decision 0070): a cut that the next step shows unsound is undone
// by running the model's updates since the mark backwards (the cells they replaced come back,
// those they appended go, those they merged away return to their old ids), with the pattern
// made again around the nodes of those cells, instead of a rebuild of every cell's basis,
// quadrature and Ke (~40 ms on the 5k organ) and the foreground AMG set-up that the rebuild's
// renumbering forced (~60-100 ms).
#include "polycut/common/error.hpp"
#include "polycut/elasticity/elastic_model.hpp"

#include <algorithm>
#include <cstdlib>
#include <numeric>

namespace polycut::elasticity {

std::uint64_t ElasticModel::mark_undo() {
    UndoMark m;
    m.serial = m_next_mark++;
    m.cells = m_cells.size();
    m.nodes = m_fixed.size() / 3;
    m.fixed = m_fixed;
    m.entry_begin = m_journal.size();
    m_marks.push_back(std::move(m));
    return m_marks.back().serial;
}

void ElasticModel::drop_mark(std::uint64_t serial) {
    std::erase_if(m_marks, [&](const UndoMark& m) { return m.serial == serial; });
    if (m_marks.empty())
        m_journal.clear();
}

void ElasticModel::forget_marks() {
    m_marks.clear();
    m_journal.clear();
}

ElasticModel::SavedCell ElasticModel::save_cell(std::size_t c, bool move) {
    SavedCell s;
    s.cell = Index(c);
    if (move)
        s.data.data = std::move(m_cells[c]);
    else
        s.data.data = m_cells[c];
    s.data.p1 = m_p1[c];
    s.data.extent2 = c < m_rest_extent2.size() ? m_rest_extent2[c] : 0.0;
    return s;
}

void ElasticModel::check_pattern_against_rebuild() {
    const auto outer = m_outer;
    const auto inner = m_inner;
    const auto diag = m_diag_slots;
    const auto scatter = m_scatter;
    const auto block = m_block_scatter;
    const auto dofs = m_dof_map;
    rebuild_pattern();
    if (outer != m_outer || inner != m_inner || diag != m_diag_slots || scatter != m_scatter
        || block != m_block_scatter || dofs != m_dof_map)
        throw StateError("ElasticModel::revert_to_mark",
            "the pattern made around the reverted cells differs from a full build");
}

bool ElasticModel::revert_to_mark(std::uint64_t serial) {
    const auto it = std::find_if(
        m_marks.begin(), m_marks.end(), [&](const UndoMark& m) { return m.serial == serial; });
    if (it == m_marks.end())
        return false;
    const UndoMark mark = std::move(*it);
    m_marks.erase(it, m_marks.end());
    const bool changed = m_journal.size() > mark.entry_begin || m_cells.size() != mark.cells
        || m_fixed != mark.fixed;
    if (!changed)
        return true;
    // Run the entries backwards. `origin` follows each cell to its id before the revert (the
    // pattern's numbering; kNone: its data comes from the journal); every node of a cell that
    // is dropped or overwritten, or comes back, is affected (a superset of the nodes whose set
    // of cells changes).
    std::vector<Index> origin(m_cells.size());
    std::iota(origin.begin(), origin.end(), Index(0));
    std::vector<char> affected(std::max(m_fixed.size() / 3, mark.nodes), 0);
    const auto touch = [&](const std::vector<Index>& nodes) {
        for (Index i : nodes)
            if (i >= 0 && std::size_t(i) < affected.size())
                affected[std::size_t(i)] = 1;
    };
    const auto put = [&](std::size_t c, ComputedCell& from) {
        touch(m_cells[c].nodes);
        touch(from.data.nodes);
        m_cells[c] = std::move(from.data);
        m_p1[c] = from.p1;
        m_rest_extent2[c] = from.extent2;
        origin[c] = kNone;
    };
    for (std::size_t k = m_journal.size(); k-- > mark.entry_begin;) {
        JournalEntry& e = m_journal[k];
        for (SavedCell& s : e.replaced)
            if (std::size_t(s.cell) < m_cells.size())
                put(std::size_t(s.cell), s.data);
        const std::size_t n = e.cells_before;
        if (e.cell_map.empty()) {
            for (std::size_t c = n; c < m_cells.size(); ++c)
                touch(m_cells[c].nodes); // appended by it
            m_cells.resize(n);
            m_p1.resize(n);
            m_rest_extent2.resize(n, 0.0);
            origin.resize(n, kNone);
            continue;
        }
        std::vector<CellData> cells(n);
        std::vector<P1Cell> p1(n);
        std::vector<double> extent2(n, 0.0);
        std::vector<Index> from(n, kNone);
        std::vector<char> taken(m_cells.size(), 0);
        for (std::size_t c = 0; c < std::min(n, e.cell_map.size()); ++c)
            if (const Index to = e.cell_map[c]; to != kNone && std::size_t(to) < m_cells.size()) {
                cells[c] = std::move(m_cells[std::size_t(to)]);
                p1[c] = m_p1[std::size_t(to)];
                extent2[c] = m_rest_extent2[std::size_t(to)];
                from[c] = origin[std::size_t(to)];
                taken[std::size_t(to)] = 1;
            }
        for (std::size_t c = 0; c < m_cells.size(); ++c)
            if (!taken[c])
                touch(m_cells[c].nodes); // made by it
        for (SavedCell& s : e.removed)
            if (std::size_t(s.cell) < n) {
                touch(s.data.data.nodes);
                cells[std::size_t(s.cell)] = std::move(s.data.data);
                p1[std::size_t(s.cell)] = s.data.p1;
                extent2[std::size_t(s.cell)] = s.data.extent2;
            }
        m_cells = std::move(cells);
        m_p1 = std::move(p1);
        m_rest_extent2 = std::move(extent2);
        origin = std::move(from);
    }
    m_journal.resize(mark.entry_begin);
    // The mesh must be the mark's again (CutPipeline::undo), cell for cell; else the caller
    // rebuilds the model from it.
    const std::size_t nn = mark.nodes;
    bool matches = m_cells.size() == mark.cells && std::size_t(m_mesh->num_cells()) == mark.cells
        && std::size_t(m_mesh->num_nodes()) == nn;
    for (std::size_t c = 0; matches && c < m_cells.size(); ++c)
        matches = m_cells[c].nodes == m_mesh->cells[c].nodes;
    if (!matches) {
        forget_marks();
        return false;
    }
    // The rotations restart from the identity, as after rebuild_topology(): the failed step's
    // are of the positions it threw away.
    m_rotation.assign(m_cells.size(), Mat3::Identity());
    affected.resize(nn); // nodes past nn are dropped
    // Other fixed DOFs (a fragment pinned) renumber the free ones: then a full pattern.
    const bool same_fixed = m_fixed.size() >= mark.fixed.size()
        && std::equal(mark.fixed.begin(), mark.fixed.end(), m_fixed.begin());
    m_fixed = mark.fixed;
    if (same_fixed)
        build_pattern(affected, std::move(origin));
    else
        rebuild_pattern();
    if (const char* v = std::getenv("POLYCUT_CHECK_UNDO"); v != nullptr && v[0] == '1')
        check_pattern_against_rebuild();
    update_mass(affected);
    return true;
}

} // namespace polycut::elasticity

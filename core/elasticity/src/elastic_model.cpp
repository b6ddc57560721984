#include "polycut/elasticity/elastic_model.hpp"

#include "nodal_dilatation.hpp"
#include "p1_batch.hpp"
#include "p1_energy.hpp"
#include "polycut/common/error.hpp"
#include "polycut/elasticity/element_stiffness.hpp"
#include "polycut/elasticity/rotation.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <span>

namespace polycut::elasticity {

std::vector<std::uint8_t> fix_nodes(const std::vector<std::uint8_t>& node_mask) {
    std::vector<std::uint8_t> dofs(3 * node_mask.size(), 0);
    for (std::size_t i = 0; i < node_mask.size(); ++i)
        if (node_mask[i])
            dofs[3 * i] = dofs[3 * i + 1] = dofs[3 * i + 2] = 1;
    return dofs;
}

ElasticModel::ElasticModel(const mesh::Mesh& mesh, const Material& material,
    const basis::BasisOptions& options, std::vector<std::uint8_t> fixed_dofs)
    : m_mesh(&mesh)
    , m_material(material)
    , m_options(options)
    , m_fixed(std::move(fixed_dofs))
    , m_nodal(options.volumetric == basis::VolumetricRule::NodalAverage
              ? std::make_unique<detail::NodalDilatation>()
              : nullptr) {
    validate(material);
    if (!m_fixed.empty() && m_fixed.size() != 3 * std::size_t(mesh.num_nodes()))
        throw InputError("fixed_dofs", "the fixed-DOF mask needs 3 entries per node");
    rebuild_topology();
}

ElasticModel::~ElasticModel() = default;
ElasticModel::ElasticModel(ElasticModel&&) noexcept = default;
ElasticModel& ElasticModel::operator=(ElasticModel&&) noexcept = default;

Eigen::Map<const MatX> ElasticModel::cell_stiffness(Index c) const {
    const MatX& K = m_cells[std::size_t(c)].stiffness;
    return { K.data(), K.rows(), K.cols() };
}

std::vector<ElasticModel::ComputedCell> ElasticModel::compute_detached(
    std::span<const Index> cells) const {
    // Each cell's data is made apart from the model, so the cells run in parallel (the mean
    // value integration of a cell-splitting cut's new cells was a quarter of its cost on the
    // organ) and a cell that cannot be made leaves the model as it was (a cut undone for it
    // then costs no model rebuild). The results do not depend on the thread count; the first
    // failure in list order is thrown, as a serial loop would.
    std::vector<ComputedCell> out(cells.size());
    std::vector<std::exception_ptr> errors(cells.size());
    const long n = long(cells.size());
    // A P1 tet or a Q1 hex takes microseconds, a general polyhedron's mean value or harmonic
    // set-up ~0.5 ms: a cut's 5-20 new cells are worth both threads (they ran on one below 33
    // cells), so they go one at a time to whichever thread is free.
    const long polyhedra = std::count_if(cells.begin(), cells.end(), [&](Index c) {
        return m_mesh->cells[std::size_t(c)].shape == mesh::CellShape::Polyhedron;
    });
    const bool parallel = m_threads > 1 && (n > 32 || polyhedra > 1);
    const int chunk = n > 256 ? 16 : 1;
#pragma omp parallel for num_threads(m_threads) schedule(dynamic, chunk) if (parallel)
    for (long k = 0; k < n; ++k) {
        try {
            compute_cell(cells[std::size_t(k)], out[std::size_t(k)]);
        } catch (...) {
            errors[std::size_t(k)] = std::current_exception();
        }
    }
    for (const std::exception_ptr& e : errors)
        if (e)
            std::rethrow_exception(e);
    return out;
}

void ElasticModel::commit_cells(std::span<const Index> cells, std::vector<ComputedCell>&& made) {
    m_rest_extent2.resize(m_cells.size(), 0.0);
    m_p1.resize(m_cells.size());
    for (std::size_t k = 0; k < cells.size(); ++k) {
        const std::size_t c = std::size_t(cells[k]);
        m_cells[c] = std::move(made[k].data);
        m_p1[c] = made[k].p1;
        m_rest_extent2[c] = made[k].extent2;
        const mesh::CellShape shape = m_mesh->cells[c].shape;
        (shape == mesh::CellShape::Tet          ? m_bases_built.p1
                : shape == mesh::CellShape::Hex ? m_bases_built.q1
                                                : m_bases_built.polyhedral)
            += 1;
    }
}

void ElasticModel::compute_cell(Index c, ComputedCell& out) const {
    CellData& cd = out.data;
    const mesh::Cell& cell = m_mesh->cells[std::size_t(c)];
    cd.nodes = cell.nodes;
    cd.integration = basis::integrate_cell(*m_mesh, c, m_options);
    cd.stiffness = element_stiffness(cd.integration, m_material, m_options.volumetric);
    const std::vector<Vec3> X = [&] {
        std::vector<Vec3> p;
        for (Index i : cell.nodes)
            p.push_back(m_mesh->rest[std::size_t(i)]);
        return p;
    }();
    if (!fit_gradients(X, cd.fit))
        throw MeshError(c, -1, "cell nodes do not span 3D: no affine fit for corotation");
    Vec3 Xc = Vec3::Zero();
    for (const Vec3& p : X)
        Xc += p;
    Xc /= double(X.size());
    double extent2 = 0;
    for (const Vec3& p : X)
        extent2 = std::max(extent2, (p - X.front()).squaredNorm());
    out.extent2 = extent2;
    cd.rest_local.resize(Index(X.size()), 3);
    for (std::size_t i = 0; i < X.size(); ++i)
        cd.rest_local.row(Index(i)) = (X[i] - Xc).transpose();
    if (cell.shape == mesh::CellShape::Polyhedron && m_options.stabilization > 0)
        stabilize_non_affine(cd.stiffness, cd.rest_local, cd.fit, m_options.stabilization);
    P1Cell& t = out.p1;
    const basis::CellIntegration& ci = cd.integration;
    if (cd.nodes.size() == 4 && ci.gradients.size() == 1 && ci.gradients[0].rows() == 4) {
        t.valid = true;
        t.volume = ci.weights[0];
        Mat3 c0 = Mat3::Zero();
        for (int i = 0; i < 4; ++i) {
            t.nodes[i] = cd.nodes[std::size_t(i)];
            for (int a = 0; a < 3; ++a)
                t.g[i][a] = ci.gradients[0](i, a);
            c0 += cd.rest_local.row(i).transpose() * ci.gradients[0].row(i);
        }
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                t.c0[a][b] = c0(a, b);
    }
}

void ElasticModel::rebuild_topology(std::vector<Index> node_map) {
    std::vector<Index> all(std::size_t(m_mesh->num_cells()));
    std::iota(all.begin(), all.end(), Index(0));
    std::vector<ComputedCell> made = compute_detached(all); // may throw: nothing changed yet
    forget_marks(); // nothing kept matches the cells after this
    m_previous_renumber_base = m_renumber_base;
    m_renumber_base = m_topology_version + 1; // the version rebuild_pattern() is about to make
    m_node_map = std::move(node_map);
    m_partition_nodes = 0; // node ids renumbered: the ranges start afresh
    const Index n = m_mesh->num_nodes();
    m_fixed.resize(3 * std::size_t(n), 0);
    m_cells.assign(all.size(), CellData {});
    m_rotation.assign(m_cells.size(), Mat3::Identity());
    m_p1.assign(m_cells.size(), P1Cell {});
    // Room for the cells cuts append: the first cut past an exact capacity moved every cell's
    // data (~6 ms of the first split cut's tick on the 5k organ). Unused room is not touched.
    const std::size_t room = all.size() + all.size() / 2 + 64;
    m_cells.reserve(room);
    m_rotation.reserve(room);
    m_p1.reserve(room);
    m_rest_extent2.reserve(room);
    commit_cells(all, std::move(made));
    rebuild_pattern();
    rebuild_mass();
}

void ElasticModel::update_cells(
    const std::vector<Index>& changed, const std::vector<Index>& cell_map) {
    const std::size_t n_cells = std::size_t(m_mesh->num_cells());
    const std::size_t n_dofs = 3 * std::size_t(m_mesh->num_nodes());
    if (n_dofs < m_fixed.size()) {
        rebuild_topology(); // nodes renumbered: nothing cached can be matched up any more
        return;
    }
    if (cell_map.empty() && n_cells < m_cells.size()) {
        rebuild_topology(); // cells removed, and no map to match them up
        return;
    }
    for (Index c : changed)
        if (c < 0 || std::size_t(c) >= n_cells)
            throw InputError("changed", "cell id out of range");
    // Only the listed cells and those no old cell moves to (appended, or with a cell map not
    // kept) get a new basis, quadrature and Ke, once (000 sec. 5.1). They are made first, apart
    // from the model: a cell that cannot be made (a cut's degenerate piece) throws with the
    // model as it was, so the undone cut needs no rebuild of the whole model (~40 ms and a
    // foreground AMG set-up of ~60 ms on the 5k organ).
    std::vector<char> kept; // with a cell map: the cells whose data moves to their new id
    if (!cell_map.empty()) {
        kept.assign(n_cells, 0);
        for (std::size_t c = 0; c < std::min(cell_map.size(), m_cells.size()); ++c)
            if (const Index to = cell_map[c]; to != kNone && std::size_t(to) < n_cells)
                kept[std::size_t(to)] = 1;
    }
    const std::size_t old_cells = cell_map.empty() ? m_cells.size() : n_cells;
    std::vector<Index> todo(changed);
    for (std::size_t c = cell_map.empty() ? old_cells : 0; c < n_cells; ++c)
        if (cell_map.empty() || !kept[c])
            todo.push_back(Index(c));
    std::sort(todo.begin(), todo.end());
    todo.erase(std::unique(todo.begin(), todo.end()), todo.end());
    std::vector<ComputedCell> made = compute_detached(todo);
    // The undo journal (elastic_undo.cpp), while a mark is open: this update, to run backwards.
    JournalEntry* entry = nullptr;
    if (!m_marks.empty()) {
        entry = &m_journal.emplace_back();
        entry->cells_before = m_cells.size();
        entry->cell_map = cell_map;
    }
    // For the pattern: nodes whose set of cells changes, and each cell's id at the last build
    // when it is the same cell.
    std::vector<char> affected(n_dofs / 3, 0);
    std::vector<Index> old_cell(n_cells, kNone);
    auto touch = [&](const std::vector<Index>& nodes) {
        for (Index i : nodes)
            if (std::size_t(i) < affected.size())
                affected[std::size_t(i)] = 1;
    };
    if (!cell_map.empty()) {
        // Cells removed (merged away): the survivors' data (everything compute_cell() makes per
        // cell) moves to their new ids, O(cells) moves instead of a new basis, quadrature and
        // Ke for every cell.
        std::vector<CellData> cells(n_cells);
        std::vector<Mat3> rotation(n_cells, Mat3::Identity());
        std::vector<P1Cell> p1(n_cells);
        std::vector<double> extent2(n_cells, 0.0);
        for (std::size_t c = 0; c < std::min(cell_map.size(), m_cells.size()); ++c) {
            const Index to = cell_map[c];
            if (to == kNone || std::size_t(to) >= n_cells) {
                touch(m_cells[c].nodes); // merged away
                if (entry)
                    entry->removed.push_back(save_cell(c, true));
                continue;
            }
            old_cell[std::size_t(to)] = Index(c);
            cells[std::size_t(to)] = std::move(m_cells[c]);
            rotation[std::size_t(to)] = m_rotation[c];
            p1[std::size_t(to)] = m_p1[c];
            extent2[std::size_t(to)] = c < m_rest_extent2.size() ? m_rest_extent2[c] : 0.0;
        }
        for (std::size_t c = cell_map.size(); entry && c < m_cells.size(); ++c)
            entry->removed.push_back(save_cell(c, true)); // past the map: dropped
        m_cells = std::move(cells);
        m_rotation = std::move(rotation);
        m_p1 = std::move(p1);
        m_rest_extent2 = std::move(extent2);
    }
    if (cell_map.empty())
        std::iota(old_cell.begin(), old_cell.begin() + std::ptrdiff_t(std::min(old_cells, n_cells)),
            Index(0));
    // Appended nodes are free until set_fixed_dofs() says otherwise.
    bool topology = n_cells != old_cells || n_dofs != m_fixed.size() || !cell_map.empty();
    m_fixed.resize(n_dofs, 0);
    m_cells.resize(n_cells);
    m_rotation.resize(n_cells, Mat3::Identity());
    m_p1.resize(n_cells);
    for (Index c : todo) {
        const std::size_t k = std::size_t(c);
        topology |= m_cells[k].nodes != m_mesh->cells[k].nodes;
        touch(m_cells[k].nodes); // before and after the cut
        touch(m_mesh->cells[k].nodes);
        old_cell[k] = kNone;
        // A child of a split starts from its parent's rotation (warm start of the polar
        // decomposition); changed cells keep theirs.
        const Index parent = m_mesh->cells[k].parent;
        if (k >= old_cells && cell_map.empty())
            m_rotation[k] = parent >= 0 && std::size_t(parent) < old_cells
                ? m_rotation[std::size_t(parent)]
                : Mat3::Identity();
    }
    if (entry)
        for (Index c : todo)
            if (cell_map.empty() ? std::size_t(c) < old_cells : kept[std::size_t(c)] != 0)
                entry->replaced.push_back(
                    save_cell(std::size_t(c), true)); // commit_cells() refills it
    commit_cells(todo, std::move(made));
    if (topology)
        build_pattern(affected, std::move(old_cell));
    update_mass(affected);
}

void ElasticModel::set_fixed_dofs(std::vector<std::uint8_t> fixed_dofs) {
    if (fixed_dofs.size() != 3 * std::size_t(m_mesh->num_nodes()))
        throw InputError("fixed_dofs", "the fixed-DOF mask needs 3 entries per node");
    if (fixed_dofs == m_fixed && !m_dof_map.empty())
        return; // after a cut: the new nodes are free, as update_cells() made them
    m_fixed = std::move(fixed_dofs);
    rebuild_pattern();
    rebuild_mass();
}

void ElasticModel::set_threads(int threads) {
    if (threads < 1)
        throw InputError("threads", "must be at least 1");
    if (threads == m_threads)
        return;
    m_threads = threads;
    rebuild_partition();
}

double ElasticModel::max_cell_stretch(const MatX3& x) const {
    // Squared ratios, one square root at the end; max is order-independent, so the result does
    // not depend on the thread count.
    const auto cells = std::ptrdiff_t(m_cells.size());
    double worst2 = 1.0;
#pragma omp parallel for num_threads(m_threads) schedule(static)                                   \
    reduction(max                                                                                  \
              : worst2) if (m_threads > 1)
    for (std::ptrdiff_t c = 0; c < cells; ++c) {
        const std::size_t begin = m_node_offset[std::size_t(c)];
        const std::size_t end = m_node_offset[std::size_t(c) + 1];
        const double rest2 = m_rest_extent2[std::size_t(c)];
        if (end - begin < 2 || !(rest2 > 0))
            continue;
        const double* xa = x.data() + 3 * m_node_list[begin];
        double now = 0;
        for (std::size_t k = begin + 1; k < end; ++k) {
            const double* xb = x.data() + 3 * m_node_list[k];
            const double dx = xb[0] - xa[0], dy = xb[1] - xa[1], dz = xb[2] - xa[2];
            now = std::max(now, dx * dx + dy * dy + dz * dz);
        }
        // NaN positions must show as an explosion
        const double ratio = now / rest2;
        worst2
            = std::isnan(ratio) ? std::numeric_limits<double>::infinity() : std::max(worst2, ratio);
    }
    return std::sqrt(worst2);
}

void ElasticModel::cell_stretch_squared(const MatX3& x, std::vector<double>& out) const {
    const auto cells = std::ptrdiff_t(m_cells.size());
    out.resize(m_cells.size());
#pragma omp parallel for num_threads(m_threads) schedule(static) if (m_threads > 1)
    for (std::ptrdiff_t c = 0; c < cells; ++c) {
        const std::size_t begin = m_node_offset[std::size_t(c)];
        const std::size_t end = m_node_offset[std::size_t(c) + 1];
        const double rest2 = m_rest_extent2[std::size_t(c)];
        double ratio = 1.0;
        if (end - begin >= 2 && rest2 > 0) {
            const double* xa = x.data() + 3 * m_node_list[begin];
            double now = 0;
            for (std::size_t k = begin + 1; k < end; ++k) {
                const double* xb = x.data() + 3 * m_node_list[k];
                const double dx = xb[0] - xa[0], dy = xb[1] - xa[1], dz = xb[2] - xa[2];
                now = std::max(now, dx * dx + dy * dy + dz * dz);
            }
            ratio = now / rest2;
            if (std::isnan(ratio))
                ratio = std::numeric_limits<double>::infinity();
        }
        out[std::size_t(c)] = ratio;
    }
}

double ElasticModel::elastic_energy(const MatX3& x, ForceMode mode) const {
    double energy = 0;
    VecX u, Ku; // reused: no allocation per cell (the energy guard calls this twice a step)
    std::vector<Mat3> rotations(m_nodal ? m_cells.size() : 0); // the nodal term's
    const double mu = m_material.mu();
    const double lambda = m_nodal ? -2.0 * mu / 3.0 : m_material.lambda(); // as assemble_cells()
    for (std::size_t c = 0; c < m_cells.size(); ++c) {
        if (const P1Cell& t = m_p1[c]; t.valid) { // closed form: no 12 x 12 product
            Mat3 R = m_rotation[c];
            energy += detail::p1_energy({ t.nodes, t.g, t.c0, t.volume, nullptr, nullptr, nullptr },
                lambda, mu, x.data(), mode == ForceMode::Corotated, R);
            if (m_nodal)
                rotations[c] = R;
            continue;
        }
        const CellData& cd = m_cells[c];
        const Index n = Index(cd.nodes.size());
        Vec3 xc = Vec3::Zero();
        for (Index i : cd.nodes)
            xc += x.row(i).transpose();
        xc /= double(n);
        Mat3 R = Mat3::Identity();
        if (mode == ForceMode::Corotated) {
            Mat3 A = Mat3::Zero();
            for (Index i = 0; i < n; ++i)
                A += (x.row(cd.nodes[std::size_t(i)]).transpose() - xc) * cd.fit.row(i);
            R = polar_rotation_warm(A, m_rotation[c]);
        }
        if (m_nodal)
            rotations[c] = R;
        u.resize(3 * n);
        for (Index i = 0; i < n; ++i)
            u.segment<3>(3 * i) = R.transpose() * (x.row(cd.nodes[std::size_t(i)]).transpose() - xc)
                - cd.rest_local.row(i).transpose();
        Ku.noalias() = cd.stiffness.selfadjointView<Eigen::Lower>() * u;
        energy += 0.5 * u.dot(Ku);
    }
    if (m_nodal)
        energy += m_nodal->energy(x, rotations, mode == ForceMode::Corotated);
    return energy;
}

void ElasticModel::reduce(const VecX& full, VecX& reduced) const {
    reduced.resize(m_num_free);
    for (Index r = 0; r < m_num_free; ++r)
        reduced(r) = full(m_free_dofs[std::size_t(r)]);
}

void ElasticModel::expand(const VecX& reduced, VecX& full) const {
    for (Index r = 0; r < m_num_free; ++r)
        full(m_free_dofs[std::size_t(r)]) = reduced(r);
}

} // namespace polycut::elasticity

namespace polycut::elasticity {

void ElasticModel::rest_rows(MatX3& X0) const {
    const auto& rest = m_mesh->rest;
    X0.resize(Index(rest.size()), 3);
    for (std::size_t i = 0; i < rest.size(); ++i)
        X0.row(Index(i)) = rest[i].transpose();
}

void ElasticModel::add_gravity(const Vec3& g, VecX& full) const {
    for (Index i = 0; i < m_mass.size(); ++i)
        full.segment<3>(3 * i) += m_mass(i) * g;
}

} // namespace polycut::elasticity

namespace polycut::elasticity {

void ElasticModel::refresh_nodal() {
    const double kappa = m_material.lambda() + 2.0 * m_material.mu() / 3.0;
    m_nodal->rebuild(m_mesh->num_nodes(), Index(m_cells.size()),
        [&](Index c) {
            const CellData& cd = m_cells[std::size_t(c)];
            return detail::NodalCellView { &cd.nodes, &cd.integration, &cd.rest_local };
        },
        kappa, { m_outer, m_nb_offset, m_nb_nodes, m_nb_start, m_nb_length, m_dof_map });
}

double ElasticModel::nodal_volumetric_omega2() const {
    return m_nodal ? m_nodal->omega2_bound(m_mass) : 0.0;
}

} // namespace polycut::elasticity

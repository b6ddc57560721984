// VTU writer: VTK XML UnstructuredGrid, ASCII. Polyhedral cells use the `faces`/`faceoffsets`
// arrays (https://vtk.org/Wiki/VTK/Polyhedron_Support): per cell, the number of faces, then per
// face its node count and node ids (outward loops); faceoffsets holds, per cell, the end of its
// entry in `faces` (-1 for cells that are not polyhedra).
#include "polycut/mesh/io_vtu.hpp"

#include "io_write.hpp"
#include "polycut/common/error.hpp"

#include <algorithm>
#include <numeric>

namespace polycut::mesh {
namespace {
constexpr int kVtkTetra = 10;
constexpr int kVtkHexahedron = 12;
constexpr int kVtkPolyhedron = 42;
constexpr const char* kCellIdName = "polycut_cell";

void check_fields(const std::vector<Field>& fields, Index rows, const char* kind) {
    for (std::size_t i = 0; i < fields.size(); ++i) {
        const Field& f = fields[i];
        const std::string where = std::string(kind) + "/" + std::to_string(i);
        if (f.name.empty() || f.name.find_first_of("\"<>&'") != std::string::npos
            || f.name == kCellIdName)
            throw InputError(where,
                "field name '" + f.name + "' must be non-empty and free of XML special characters");
        if (f.values.rows() != rows || f.values.cols() < 1)
            throw InputError(where,
                "field '" + f.name + "' has " + std::to_string(f.values.rows()) + " x "
                    + std::to_string(f.values.cols()) + " values; expected " + std::to_string(rows)
                    + " rows and at least one column");
    }
}

/// Appends one field's DataArray, its rows taken in `order`.
void append_field(std::string& out, const Field& f, const std::vector<Index>* order) {
    out += "        <DataArray type=\"Float64\" Name=\"" + f.name + "\" NumberOfComponents=\""
        + std::to_string(f.values.cols()) + "\" format=\"ascii\">\n";
    for (Eigen::Index i = 0; i < f.values.rows(); ++i) {
        const Eigen::Index r = order != nullptr ? (*order)[std::size_t(i)] : i;
        out += "         ";
        for (Eigen::Index k = 0; k < f.values.cols(); ++k) {
            out += ' ';
            io::append_number(out, f.values(r, k));
        }
        out += '\n';
    }
    out += "        </DataArray>\n";
}

template <class Ints>
void append_int_array(std::string& out, const char* type, const char* name, const Ints& values) {
    out += "        <DataArray type=\"";
    out += type;
    out += "\" Name=\"";
    out += name;
    out += "\" format=\"ascii\">\n         ";
    std::size_t column = 0;
    for (auto v : values) {
        out += ' ';
        io::append_number(out, long(v));
        if (++column % 16 == 0)
            out += "\n         ";
    }
    out += "\n        </DataArray>\n";
}

/// Writes with positions given as a flat array [x0 y0 z0 x1 ...] [m].
void write_vtu_flat(const std::string& path, const Mesh& mesh, const double* xyz,
    const std::vector<Field>& point_fields, const std::vector<Field>& cell_fields,
    VtuCellTypes cell_types) {
    check_fields(point_fields, mesh.num_nodes(), "point_fields");
    check_fields(cell_fields, mesh.num_cells(), "cell_fields");
    const bool any_polyhedron = std::any_of(mesh.cells.begin(), mesh.cells.end(),
        [](const Cell& c) { return c.shape == CellShape::Polyhedron; });
    const bool all_polyhedra = cell_types == VtuCellTypes::AllPolyhedra
        || (cell_types == VtuCellTypes::Auto && any_polyhedron);

    // meshio 5 groups polyhedra by node count and misassigns cell data unless the groups come
    // in ascending order (meshio PR #1463), so polyhedral files list the cells sorted by node
    // count (stable) and carry each file cell's Mesh index as "polycut_cell".
    std::vector<Index> order(std::size_t(mesh.num_cells()));
    std::iota(order.begin(), order.end(), 0);
    if (all_polyhedra)
        std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) {
            return mesh.cells[std::size_t(a)].nodes.size()
                < mesh.cells[std::size_t(b)].nodes.size();
        });

    std::vector<long> connectivity, offsets, faces, faceoffsets;
    std::vector<int> types;
    bool has_polyhedra = false;
    for (const Index c : order) {
        const Cell& cell = mesh.cells[std::size_t(c)];
        connectivity.insert(connectivity.end(), cell.nodes.begin(), cell.nodes.end());
        offsets.push_back(long(connectivity.size()));
        if (!all_polyhedra && cell.shape != CellShape::Polyhedron) {
            types.push_back(cell.shape == CellShape::Tet ? kVtkTetra : kVtkHexahedron);
            faceoffsets.push_back(-1);
            continue;
        }
        has_polyhedra = true;
        types.push_back(kVtkPolyhedron);
        faces.push_back(long(cell.faces.size()));
        for (Index f : cell.faces) {
            const auto loop = mesh.face_loop(f, c);
            faces.push_back(long(loop.size()));
            faces.insert(faces.end(), loop.begin(), loop.end());
        }
        faceoffsets.push_back(long(faces.size()));
    }

    std::string out;
    out.reserve(64 * std::size_t(mesh.num_nodes()) + 48 * connectivity.size() + 1024);
    out += "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
           "  <UnstructuredGrid>\n";
    out += "    <Piece NumberOfPoints=\"" + std::to_string(mesh.num_nodes()) + "\" NumberOfCells=\""
        + std::to_string(mesh.num_cells()) + "\">\n";
    if (!point_fields.empty()) {
        out += "      <PointData>\n";
        for (const Field& f : point_fields)
            append_field(out, f, nullptr);
        out += "      </PointData>\n";
    }
    if (!cell_fields.empty() || all_polyhedra) {
        out += "      <CellData>\n";
        for (const Field& f : cell_fields)
            append_field(out, f, &order);
        if (all_polyhedra)
            append_int_array(out, "Int64", kCellIdName, order);
        out += "      </CellData>\n";
    }
    out += "      <Points>\n"
           "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (Index n = 0; n < mesh.num_nodes(); ++n) {
        out += "         ";
        for (int k = 0; k < 3; ++k) {
            out += ' ';
            io::append_number(out, xyz[3 * std::size_t(n) + std::size_t(k)]);
        }
        out += '\n';
    }
    out += "        </DataArray>\n"
           "      </Points>\n"
           "      <Cells>\n";
    append_int_array(out, "Int64", "connectivity", connectivity);
    append_int_array(out, "Int64", "offsets", offsets);
    append_int_array(out, "UInt8", "types", types);
    if (has_polyhedra) {
        append_int_array(out, "Int64", "faces", faces);
        append_int_array(out, "Int64", "faceoffsets", faceoffsets);
    }
    out += "      </Cells>\n"
           "    </Piece>\n"
           "  </UnstructuredGrid>\n"
           "</VTKFile>\n";
    io::write_file(path, out);
}
} // namespace

void write_vtu(const std::string& path, const Mesh& mesh, const std::vector<Vec3>* positions,
    const std::vector<Field>& point_fields, const std::vector<Field>& cell_fields,
    VtuCellTypes cell_types) {
    const std::vector<Vec3>& x = positions != nullptr ? *positions : mesh.rest;
    if (x.size() != mesh.rest.size())
        throw InputError("positions",
            "got " + std::to_string(x.size()) + " positions for " + std::to_string(mesh.rest.size())
                + " nodes");
    std::vector<double> xyz;
    xyz.reserve(3 * x.size());
    for (const Vec3& p : x)
        xyz.insert(xyz.end(), { p.x(), p.y(), p.z() });
    write_vtu_flat(path, mesh, xyz.data(), point_fields, cell_fields, cell_types);
}

void write_vtu(const std::string& path, const Mesh& mesh, const MatX3& positions,
    const std::vector<Field>& point_fields, const std::vector<Field>& cell_fields,
    VtuCellTypes cell_types) {
    if (positions.rows() != mesh.num_nodes())
        throw InputError("positions",
            "got " + std::to_string(positions.rows()) + " positions for "
                + std::to_string(mesh.num_nodes()) + " nodes");
    write_vtu_flat(path, mesh, positions.data(), point_fields, cell_fields, cell_types);
}

} // namespace polycut::mesh

#include "polycut/mesh/packed.hpp"

namespace polycut::mesh {

void pack(const Mesh& m, PackedMesh& out) {
    out.rest = m.rest;
    const std::size_t nf = m.faces.size(), nc = m.cells.size();
    out.face_offset.resize(nf + 1);
    out.face_owner.resize(nf);
    out.face_neighbour.resize(nf);
    out.face_parent.resize(nf);
    out.face_tag.resize(nf);
    out.face_nodes.clear();
    out.face_offset[0] = 0;
    for (std::size_t f = 0; f < nf; ++f) {
        const Face& face = m.faces[f];
        out.face_nodes.insert(out.face_nodes.end(), face.nodes.begin(), face.nodes.end());
        out.face_offset[f + 1] = Index(out.face_nodes.size());
        out.face_owner[f] = face.owner;
        out.face_neighbour[f] = face.neighbour;
        out.face_parent[f] = face.parent;
        out.face_tag[f] = face.tag;
    }
    out.cell_node_offset.resize(nc + 1);
    out.cell_face_offset.resize(nc + 1);
    out.cell_shape.resize(nc);
    out.cell_parent.resize(nc);
    out.cell_nodes.clear();
    out.cell_faces.clear();
    out.cell_node_offset[0] = out.cell_face_offset[0] = 0;
    for (std::size_t c = 0; c < nc; ++c) {
        const Cell& cell = m.cells[c];
        out.cell_nodes.insert(out.cell_nodes.end(), cell.nodes.begin(), cell.nodes.end());
        out.cell_faces.insert(out.cell_faces.end(), cell.faces.begin(), cell.faces.end());
        out.cell_node_offset[c + 1] = Index(out.cell_nodes.size());
        out.cell_face_offset[c + 1] = Index(out.cell_faces.size());
        out.cell_shape[c] = cell.shape;
        out.cell_parent[c] = cell.parent;
    }
}

Mesh unpack(const PackedMesh& p) {
    Mesh m;
    m.rest = p.rest;
    const std::size_t nf = p.face_owner.size(), nc = p.cell_shape.size();
    m.faces.resize(nf);
    for (std::size_t f = 0; f < nf; ++f) {
        Face& face = m.faces[f];
        face.nodes.assign(
            p.face_nodes.begin() + p.face_offset[f], p.face_nodes.begin() + p.face_offset[f + 1]);
        face.owner = p.face_owner[f];
        face.neighbour = p.face_neighbour[f];
        face.parent = p.face_parent[f];
        face.tag = p.face_tag[f];
    }
    m.cells.resize(nc);
    for (std::size_t c = 0; c < nc; ++c) {
        Cell& cell = m.cells[c];
        cell.nodes.assign(p.cell_nodes.begin() + p.cell_node_offset[c],
            p.cell_nodes.begin() + p.cell_node_offset[c + 1]);
        cell.faces.assign(p.cell_faces.begin() + p.cell_face_offset[c],
            p.cell_faces.begin() + p.cell_face_offset[c + 1]);
        cell.shape = p.cell_shape[c];
        cell.parent = p.cell_parent[c];
    }
    return m;
}

} // namespace polycut::mesh

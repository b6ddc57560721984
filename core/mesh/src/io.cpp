// Volume mesh reader dispatch by file extension.
#include "polycut/mesh/io.hpp"

#include "polycut/common/error.hpp"

#include <filesystem>

namespace polycut::mesh {

Mesh read_volume_mesh(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".msh")
        return read_gmsh(path);
    if (ext == ".node" || ext == ".ele")
        return read_tetgen(path);
    throw FileError(
        path, 0, "unknown volume mesh format '" + ext + "' (expected .msh, .node or .ele)");
}

} // namespace polycut::mesh

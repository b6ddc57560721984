#include "polycut/common/error.hpp"

namespace polycut {
namespace {
    std::string compose(const std::string& where, const std::string& what)
    {
        return where.empty() ? what : where + ": " + what;
    }
    std::string mesh_where(long cell, long face)
    {
        std::string s;
        if (cell >= 0)
            s = "cell " + std::to_string(cell);
        if (face >= 0)
            s += (s.empty() ? "" : " ") + std::string("face ") + std::to_string(face);
        return s;
    }
} // namespace

Error::Error(std::string where, const std::string& what)
    : std::runtime_error(compose(where, what))
    , m_where(std::move(where))
    , m_problem(what)
{
}

FileError::FileError(const std::string& path, long line, const std::string& what)
    : Error(line > 0 ? path + ":" + std::to_string(line) : path, what)
    , m_path(path)
    , m_line(line)
{
}

MeshError::MeshError(long cell, long face, const std::string& what)
    : Error(mesh_where(cell, face), what)
    , m_cell(cell)
    , m_face(face)
{
}

} // namespace polycut

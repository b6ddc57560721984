// Typed errors for bad input at construction time (scenes, meshes, files). Each error says what
// is wrong and where: a JSON pointer, a file and line, or a cell and face.
#pragma once

#include <stdexcept>
#include <string>

namespace polycut {

/// Base of every error polycut throws for bad input. `where()` locates the problem.
class Error : public std::runtime_error {
public:
    Error(std::string where, const std::string& what);
    /// Location: a JSON pointer ("/material/poisson_ratio"), "file:line", or "cell 12 face 3".
    const std::string& where() const noexcept { return m_where; }
    /// The problem alone, without the location.
    const std::string& problem() const noexcept { return m_problem; }

private:
    std::string m_where;
    std::string m_problem;
};

/// A scene document is invalid; `where()` is a JSON pointer into it.
class SceneError : public Error {
public:
    using Error::Error;
};

/// A mesh file could not be read; `where()` is "path:line".
class FileError : public Error {
public:
    FileError(const std::string& path, long line, const std::string& what);
    const std::string& path() const noexcept { return m_path; }
    long line() const noexcept { return m_line; }

private:
    std::string m_path;
    long m_line;
};

/// A mesh is geometrically or topologically invalid; `where()` names the cell and face.
class MeshError : public Error {
public:
    MeshError(long cell, long face, const std::string& what);
    long cell() const noexcept { return m_cell; }
    long face() const noexcept { return m_face; }

private:
    long m_cell;
    long m_face;
};

/// An argument to an API call is invalid (non-finite number, degenerate triangle, ...).
class InputError : public Error {
public:
    using Error::Error;
};

/// Valid input the current state cannot carry out (a force at a point with no material near
/// it); nothing was changed. `where()` names the argument ("point").
class StateError : public Error {
public:
    using Error::Error;
};

} // namespace polycut

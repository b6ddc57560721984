// .pvd collection writer (see io_pvd.hpp).
#include "polycut/mesh/io_pvd.hpp"

#include "io_write.hpp"
#include "polycut/common/error.hpp"

#include <cmath>

namespace polycut::mesh {

PvdCollection::PvdCollection(std::string path)
    : m_path(std::move(path)) { }

void PvdCollection::add(double time, const std::string& file) {
    const std::string where = m_path + "/DataSet/" + std::to_string(m_steps.size());
    if (!std::isfinite(time) || (!m_steps.empty() && time < m_steps.back().time))
        throw InputError(where + "/timestep",
            "time must be finite and not before the previous step's, got " + std::to_string(time));
    if (file.empty() || file.find_first_of("\"<>&'") != std::string::npos)
        throw InputError(
            where + "/file", "file name '" + file + "' must be non-empty and free of XML specials");
    std::string out = "<?xml version=\"1.0\"?>\n"
                      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                      "  <Collection>\n";
    auto append = [&out](double t, const std::string& f) {
        out += "    <DataSet timestep=\"";
        io::append_number(out, t);
        out += "\" group=\"\" part=\"0\" file=\"" + f + "\"/>\n";
    };
    for (const Step& s : m_steps)
        append(s.time, s.file);
    append(time, file);
    out += "  </Collection>\n"
           "</VTKFile>\n";
    io::write_file(m_path, out);
    m_steps.push_back({ time, file });
}

} // namespace polycut::mesh

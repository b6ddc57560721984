// ParaView data collection (.pvd): one file that lists the .vtu steps of a session with their
// times, so a ParaView user opens one file and scrubs through the session
// (https://www.paraview.org/Wiki/ParaView/Data_formats#PVD_File_Format).
#pragma once

#include <string>
#include <vector>

namespace polycut::mesh {

/// A growing .pvd collection. Each add() rewrites the whole file (to a temporary name, then
/// renamed), so the collection on disk is complete after every step, also when the run stops
/// early.
class PvdCollection {
public:
    /// One listed step.
    struct Step {
        double time = 0; ///< simulated time [s]
        std::string file; ///< the step's file, relative to the .pvd's directory
    };

    /// `path` is the .pvd file to write (its directory must exist).
    explicit PvdCollection(std::string path);

    /// Lists `file` (relative to the .pvd's directory, e.g. "frame_000010.vtu") at `time` [s]
    /// and rewrites the .pvd. Throws InputError when the time is not finite or goes backwards
    /// or the name holds XML special characters, FileError when the file cannot be written;
    /// the collection is unchanged then.
    void add(double time, const std::string& file);

    /// The steps listed so far, in order.
    const std::vector<Step>& steps() const { return m_steps; }
    /// The .pvd file.
    const std::string& path() const { return m_path; }

private:
    std::string m_path;
    std::vector<Step> m_steps;
};

} // namespace polycut::mesh

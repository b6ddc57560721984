// The headless runner's JSON report (issue 2 item 6, issue 3 item 4, issue 5 item 7, issue 18
// items 1-2: the meshing report).
#pragma once

#include "polycut/common/stats.hpp"
#include "polycut/sim/simulation.hpp"

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace polycut::run {

/// Everything measured during a run, turned into JSON by to_json().
struct RunRecord {
    std::string scene;
    std::string method;
    sim::MeshingSummary meshing; ///< CGAL meshing of the geometry, reported when meshed
    sim::MeshStats before;
    sim::MeshStats after;
    long steps = 0;
    std::vector<double> step_ms, assembly_ms, solve_ms;
    std::vector<double> iterations;
    std::vector<double> cut_ms;
    double max_residual = 0;
    long rolled_back = 0;
    std::vector<std::string> warnings;
    bool has_cuts = false;
    long cut_triangles = 0;
    long pieces_fixed = 0; ///< static scenes: free pieces fixed at one face after cuts
    long failed_cuts = 0; ///< cuts the simulation could not apply (undone, reported)
    long undone_cuts = 0; ///< steps that undid the cuts before them (the model was unsound)
    std::vector<std::pair<std::string, Vec3>> probes;
    // Cost (issue 17 item 1)
    double setup_ms = 0; ///< wall time of building the simulation from the scene [ms]
    double setup_cpu_ms = 0; ///< CPU time of the same, all threads [ms]
    std::vector<double> step_cpu_ms; ///< CPU time of each step, all threads [ms]
    long setup_rss_kb = 0; ///< peak resident memory after set-up [KiB]
    long peak_rss_kb = 0; ///< peak resident memory of the run [KiB]
    sim::ModelStats model; ///< DOFs, nonzeros, cells by kind (at the end of the run)
    /// What the scene built and what it cost (issue 17 item 6), taken at the end of the run
    sim::BuildReport build;
    /// --samples: rest points and the displacement there at the end (inside 0: in no cell)
    std::vector<Vec3> sample_points, sample_u;
    std::vector<std::uint8_t> sample_inside;
    // Contact (issue 15): per step, and per tool/obstacle the largest force over the run
    std::vector<double> contact_ms; ///< contact detection and reactions of each step [ms]
    std::vector<double> contact_points; ///< penalty points (samples in contact) per step
    struct BodyPeak {
        std::string kind, name;
        long id = 0;
        Vec3 max_force = Vec3::Zero(); ///< the force of largest magnitude over the run [N]
        long max_force_tick = 0;
        double max_depth = 0; ///< [m]
        Vec3 final_force = Vec3::Zero(); ///< after the last step [N]
    };
    std::vector<BodyPeak> bodies;
    /// Folds a step's reactions into `bodies` and the per-step series.
    void add_contact(const std::vector<sim::BodyReaction>& reactions, double ms, long tick);
};

nlohmann::json summary_json(const Summary& s);
nlohmann::json to_json(const RunRecord& r);

} // namespace polycut::run

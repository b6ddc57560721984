// Validation of the Mesh_3 options shared by the implicit and the surface meshers, and the
// default progress sink.
#include "polycut/meshing/options.hpp"

#include "polycut/common/error.hpp"

#include <cmath>
#include <cstdio>

namespace polycut::meshing {

void check_options(const MeshingOptions& o) {
    auto positive = [](double v) { return std::isfinite(v) && v > 0; };
    if (!positive(o.cell_size))
        throw InputError("options.cell_size", "cell size must be finite and > 0");
    if (!std::isfinite(o.facet_distance))
        throw InputError("options.facet_distance", "facet distance must be finite");
    if (!(o.facet_angle > 0 && o.facet_angle <= 30))
        throw InputError("options.facet_angle", "facet angle must be in (0, 30] degrees");
    if (!(o.cell_radius_edge_ratio >= 2 && std::isfinite(o.cell_radius_edge_ratio)))
        throw InputError("options.cell_radius_edge_ratio", "radius-edge ratio must be >= 2");
    if (!std::isfinite(o.feature_angle))
        throw InputError("options.feature_angle", "feature angle must be finite");
    if (!(o.sliver_bound >= 0 && o.sliver_bound < 60))
        throw InputError("options.sliver_bound", "sliver bound must be in [0, 60) degrees");
    if (std::isnan(o.refine_time_limit))
        throw InputError("options.refine_time_limit", "refine time limit must be a number");
}

void select_optimizers(MeshingOptions& o, const std::vector<std::string>& names) {
    o.lloyd = o.odt = o.perturb = o.exude = false;
    for (const std::string& name : names) {
        if (name == "lloyd")
            o.lloyd = true;
        else if (name == "odt")
            o.odt = true;
        else if (name == "perturb")
            o.perturb = true;
        else if (name == "exude")
            o.exude = true;
        else
            throw InputError("optimize",
                "unknown Mesh_3 optimiser \"" + name
                    + "\" (expected \"lloyd\", \"odt\", \"perturb\", \"exude\")");
    }
}

void print_progress(const std::string& line) {
    std::fprintf(stderr, "polycut meshing: %s\n", line.c_str());
}

} // namespace polycut::meshing

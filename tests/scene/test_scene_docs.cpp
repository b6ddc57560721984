// docs/scenes.md against the code (issue 17 item 7, docs/decisions/0051): every default the
// reference tables state for the scene's material, basis, dg, integrator, solver and cutting keys
// (and the top-level method) is the default a scene file without that key gets, and that is the
// default-constructed scene's, which takes it from the module option structs. A documented key
// with a scalar default the test does not know, or a known key the doc no longer documents,
// fails too: the doc and the test move together.
//
// Doc format read here: a "## section" heading, then a markdown table whose header row has a
// `default` column; each row's first cell is the key in backticks, the default cell starts with
// a number, a quoted string in backticks (`"jacobi"`) or true/false (anything else, e.g.
// "required" or "see below", is not a scalar and is skipped). The solver's `amg` row lists its
// keys inline as "`key` (..., default X)".
#include "names.hpp" // the scene's private name tables (tests/scene/CMakeLists.txt)
#include "polycut/common/error.hpp"
#include "polycut/scene/scene.hpp"

#include <cmath>
#include <fstream>
#include <functional>
#include <gtest/gtest.h>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace polycut;
using namespace polycut::scene;

namespace {

/// A scene file with only the required keys: what a user gets for everything else.
const char* kMinimal = R"({
  "name": "defaults",
  "geometry": {"type": "box", "size": [0.1, 0.1, 0.1]},
  "material": {"youngs_modulus": 1e4}
})";

/// A value as the doc writes it: a number, a name ("jacobi") or a boolean ("true").
struct Value {
    enum class Kind { Number, Name, Bool } kind = Kind::Number;
    double number = 0;
    std::string text;
};

Value num(double x) {
    return { Value::Kind::Number, x, "" };
}
Value name(const char* s) {
    return { Value::Kind::Name, 0, s };
}
Value boolean(bool b) {
    return { Value::Kind::Bool, 0, b ? "true" : "false" };
}

/// The default of every documented key, read from a scene.
using Getter = std::function<Value(const Scene&)>;
std::map<std::string, Getter> getters() {
    std::map<std::string, Getter> g;
    g["/method"] = [](const Scene& s) { return name(to_string(s.method)); };
    g["material/poisson_ratio"] = [](const Scene& s) { return num(s.material.poisson_ratio); };
    g["material/density"] = [](const Scene& s) { return num(s.material.density); };
    g["material/rayleigh_mass"] = [](const Scene& s) { return num(s.material.rayleigh_mass); };
    g["material/rayleigh_stiffness"]
        = [](const Scene& s) { return num(s.material.rayleigh_stiffness); };
    g["basis/degree"] = [](const Scene& s) { return num(s.basis.degree); };
    g["basis/rule"] = [](const Scene& s) { return name(to_string(s.basis.rule)); };
    g["basis/gauss_degree"] = [](const Scene& s) { return num(s.basis.gauss_degree); };
    g["basis/harmonic_xi"] = [](const Scene& s) { return num(s.basis.harmonic_xi); };
    g["basis/volumetric"] = [](const Scene& s) { return name(to_string(s.basis.volumetric)); };
    g["dg/flux"] = [](const Scene& s) { return name(to_string(s.dg.flux)); };
    g["dg/penalty"] = [](const Scene& s) { return num(s.dg.penalty); };
    g["dg/dirichlet_penalty"] = [](const Scene& s) { return num(s.dg.dirichlet_penalty); };
    g["dg/refine_stress"] = [](const Scene& s) { return num(s.dg.refine_stress); };
    g["dg/refine_levels"] = [](const Scene& s) { return num(s.dg.refine_levels); };
    g["dg/lambda_penalty"] = [](const Scene& s) { return name(to_string(s.dg.lambda_penalty)); };
    g["integrator/type"] = [](const Scene& s) { return name(to_string(s.integrator.type)); };
    g["integrator/dt"] = [](const Scene& s) { return num(s.integrator.dt); };
    g["integrator/corotated"] = [](const Scene& s) { return boolean(s.integrator.corotated); };
    g["integrator/static_mode"]
        = [](const Scene& s) { return name(to_string(s.integrator.static_mode)); };
    g["integrator/tolerance"] = [](const Scene& s) { return num(s.integrator.tolerance); };
    g["integrator/max_iterations"]
        = [](const Scene& s) { return num(s.integrator.max_iterations); };
    g["integrator/stiffness_every"]
        = [](const Scene& s) { return num(s.integrator.stiffness_every); };
    g["integrator/energy_guard"]
        = [](const Scene& s) { return boolean(s.integrator.energy_guard); };
    g["integrator/threads"] = [](const Scene& s) { return num(s.integrator.threads); };
    g["solver/type"] = [](const Scene& s) { return name(to_string(s.solver.type)); };
    g["solver/preconditioner"]
        = [](const Scene& s) { return name(to_string(s.solver.preconditioner)); };
    g["solver/tolerance"] = [](const Scene& s) { return num(s.solver.tolerance); };
    g["solver/load_tolerance"] = [](const Scene& s) { return num(s.solver.load_tolerance); };
    g["solver/max_iterations"] = [](const Scene& s) { return num(s.solver.max_iterations); };
    g["solver/iteration_budget"] = [](const Scene& s) { return num(s.solver.iteration_budget); };
    g["solver/refactor_every"] = [](const Scene& s) { return num(s.solver.refactor_every); };
    g["solver/refactor_iterations"]
        = [](const Scene& s) { return num(s.solver.refactor_iterations); };
    g["solver/warm_start"] = [](const Scene& s) { return name(to_string(s.solver.warm_start)); };
    g["solver/start_vectors"] = [](const Scene& s) { return num(s.solver.start_vectors); };
    g["solver/amg/strong_threshold"]
        = [](const Scene& s) { return num(s.solver.amg_strong_threshold); };
    g["solver/amg/aggressive_levels"]
        = [](const Scene& s) { return num(s.solver.amg_aggressive_levels); };
    g["solver/amg/interpolation_max_elements"]
        = [](const Scene& s) { return num(s.solver.amg_interpolation_max_elements); };
    g["solver/amg/max_coarse_size"]
        = [](const Scene& s) { return num(s.solver.amg_max_coarse_size); };
    g["solver/amg/rigid_body_modes"]
        = [](const Scene& s) { return boolean(s.solver.amg_rigid_body_modes); };
    g["solver/amg/node_blocks"] = [](const Scene& s) { return boolean(s.solver.amg_node_blocks); };
    g["solver/amg/background_solves"]
        = [](const Scene& s) { return num(s.solver.amg_background_solves); };
    g["solver/amg/background_serial"]
        = [](const Scene& s) { return boolean(s.solver.amg_background_serial); };
    g["solver/amg/refresh_delay"] = [](const Scene& s) { return num(s.solver.amg_refresh_delay); };
    g["cutting/method"] = [](const Scene& s) { return name(to_string(s.cutting.method)); };
    g["cutting/snap_distance"] = [](const Scene& s) { return num(s.cutting.snap_distance); };
    g["cutting/sliver_volume"] = [](const Scene& s) { return num(s.cutting.sliver_volume); };
    g["cutting/max_cells_per_tick"]
        = [](const Scene& s) { return num(double(s.cutting.max_cells_per_tick)); };
    g["cutting/max_model_growth"] = [](const Scene& s) { return num(s.cutting.max_model_growth); };
    return g;
}

/// Sections whose tables are checked, by the first word of their "## " heading.
const std::map<std::string, std::string> kSections
    = { { "Top", "/" }, { "material", "material/" }, { "basis", "basis/" }, { "dg", "dg/" },
          { "integrator", "integrator/" }, { "solver", "solver/" }, { "cutting", "cutting/" } };

/// A scalar at the start of a default cell, if there is one.
std::optional<Value> parse_scalar(const std::string& cell) {
    static const std::regex quoted(R"re(^`"([a-z_0-9]+)"`)re");
    static const std::regex number(R"(^[-+]?[0-9][0-9.]*(e[-+]?[0-9]+)?)");
    static const std::regex boolean_re(R"(^(true|false)\b)");
    std::smatch m;
    if (std::regex_search(cell, m, quoted))
        return name(m[1].str().c_str());
    if (std::regex_search(cell, m, boolean_re))
        return boolean(m[1].str() == "true");
    if (std::regex_search(cell, m, number))
        return num(std::stod(m[0].str()));
    return std::nullopt;
}

std::vector<std::string> split_row(const std::string& line) {
    std::vector<std::string> cells;
    std::string cell;
    bool escaped = false;
    for (char c : line.substr(line.find('|') + 1)) {
        if (c == '|' && !escaped) {
            const auto a = cell.find_first_not_of(' ');
            const auto b = cell.find_last_not_of(' ');
            cells.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
            cell.clear();
        } else
            cell += c;
        escaped = c == '\\';
    }
    return cells;
}

struct DocDefault {
    std::string key; ///< "solver/tolerance"
    Value value;
    int line = 0;
};

/// The scalar defaults of the checked sections of docs/scenes.md.
std::vector<DocDefault> read_doc_defaults(const std::string& path) {
    std::ifstream in(path);
    EXPECT_TRUE(in.good()) << path;
    std::vector<DocDefault> out;
    std::string line, prefix;
    bool in_section = false;
    int default_column = -1;
    int number = 0;
    static const std::regex amg_key(R"(`([a-z_]+)` \([^`]*?default ([^):;,]+))");
    while (std::getline(in, line)) {
        ++number;
        if (line.rfind("## ", 0) == 0) {
            std::istringstream words(line.substr(3));
            std::string first;
            words >> first;
            const auto it = kSections.find(first);
            in_section = it != kSections.end();
            prefix = in_section ? it->second : "";
            default_column = -1;
            continue;
        }
        if (!in_section || line.empty() || line[0] != '|') {
            if (line.empty() || line[0] != '|')
                default_column = -1; // a table ends at its first non-row line
            continue;
        }
        const std::vector<std::string> cells = split_row(line);
        if (default_column < 0) {
            for (std::size_t c = 0; c < cells.size(); ++c)
                if (cells[c] == "default")
                    default_column = int(c);
            continue;
        }
        if (cells.empty() || cells[0].rfind("---", 0) == 0 || cells[0].size() < 3
            || cells[0].front() != '`' || int(cells.size()) <= default_column)
            continue;
        const std::string key = cells[0].substr(1, cells[0].size() - 2);
        const std::string full = prefix == "/" ? "/" + key : prefix + key;
        if (full == "solver/amg") {
            const std::string& text = cells.back();
            for (std::sregex_iterator it(text.begin(), text.end(), amg_key), end; it != end; ++it)
                if (auto v = parse_scalar((*it)[2].str()))
                    out.push_back({ full + "/" + (*it)[1].str(), *v, number });
            continue;
        }
        if (auto v = parse_scalar(cells[std::size_t(default_column)]))
            out.push_back({ full, *v, number });
    }
    return out;
}

::testing::AssertionResult same(const Value& doc, const Value& code) {
    if (doc.kind != code.kind)
        return ::testing::AssertionFailure()
            << "different kinds: doc \"" << doc.text << "\" " << doc.number << ", code \""
            << code.text << "\" " << code.number;
    if (doc.kind == Value::Kind::Number) {
        if (std::abs(doc.number - code.number) <= 1e-12 * std::abs(code.number))
            return ::testing::AssertionSuccess();
        return ::testing::AssertionFailure() << "doc " << doc.number << ", code " << code.number;
    }
    if (doc.text == code.text)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
        << "doc \"" << doc.text << "\", code \"" << code.text << "\"";
}

} // namespace

TEST(SceneDocs, DocumentedDefaultsAreTheParsedAndTheModuleDefaults) {
    const std::vector<DocDefault> doc
        = read_doc_defaults(std::string(POLYCUT_SOURCE_DIR) + "/docs/scenes.md");
    const auto get = getters();
    const Scene parsed = parse_scene(kMinimal);
    std::set<std::string> seen;
    for (const DocDefault& d : doc) {
        const auto it = get.find(d.key);
        if (it == get.end()) {
            ADD_FAILURE() << "docs/scenes.md:" << d.line << ": `" << d.key
                          << "` has a default this test does not check: add it to getters()";
            continue;
        }
        seen.insert(d.key);
        EXPECT_TRUE(same(d.value, it->second(parsed)))
            << "docs/scenes.md:" << d.line << ": `" << d.key << "` (a scene file without it)";
    }
    for (const auto& [key, getter] : get)
        EXPECT_TRUE(seen.count(key)) << "`" << key << "`: no default in docs/scenes.md";
    EXPECT_GE(doc.size(), get.size());
}

TEST(SceneDocs, DefaultConstructedSceneIsTheParsedOne) {
    // The struct defaults are what a scene file without the key gets; the one exception is the
    // cut method, whose default depends on the element method (snap for tet).
    const Scene parsed = parse_scene(kMinimal);
    const Scene constructed;
    for (const auto& [key, getter] : getters()) {
        if (key == "cutting/method")
            continue;
        EXPECT_TRUE(same(getter(constructed), getter(parsed))) << key;
    }
    EXPECT_EQ(parsed.cutting.method, CutMethod::Snap);
    EXPECT_EQ(parse_scene(R"({"name": "d", "method": "hex",
        "geometry": {"type": "box", "size": [0.1, 0.1, 0.1], "elements": "hex"},
        "material": {"youngs_modulus": 1e4}})")
                  .cutting.method,
        constructed.cutting.method);
}

TEST(SceneDocs, SceneDefaultsAreTheModuleDefaults) {
    // One source of truth (docs/decisions/0051): the scene's defaults are the option structs'.
    const Scene s;
    const elasticity::Material mat;
    EXPECT_EQ(s.material.poisson_ratio, mat.poisson_ratio);
    EXPECT_EQ(s.material.density, mat.density);
    const basis::BasisOptions bo;
    EXPECT_EQ(s.basis.harmonic_xi, bo.harmonic_xi);
    EXPECT_EQ(s.basis.gauss_degree, bo.gauss_degree);
    EXPECT_EQ(s.basis.rule, bo.rule);
    EXPECT_EQ(s.basis.volumetric, bo.volumetric);
    const dg::DgOptions dgo;
    EXPECT_EQ(s.basis.degree, dgo.degree);
    EXPECT_EQ(s.dg.flux, dgo.flux);
    EXPECT_EQ(s.dg.penalty, dgo.penalty);
    EXPECT_EQ(s.dg.dirichlet_penalty, dgo.dirichlet_penalty);
    EXPECT_EQ(s.dg.lambda_penalty, dgo.lambda_penalty);
    const integrate::IntegratorOptions it;
    EXPECT_EQ(s.integrator.type, it.kind);
    EXPECT_EQ(s.integrator.dt, it.dt);
    EXPECT_EQ(s.integrator.static_mode, it.static_mode);
    EXPECT_EQ(s.integrator.tolerance, it.static_tolerance);
    EXPECT_EQ(s.integrator.max_iterations, it.static_max_iterations);
    EXPECT_EQ(s.integrator.threads, it.threads);
    EXPECT_EQ(s.integrator.stiffness_every, it.stiffness_every);
    EXPECT_EQ(s.integrator.energy_guard, it.energy_guard);
    EXPECT_EQ(s.solver.tolerance, it.solver.relative_tolerance);
    EXPECT_EQ(s.solver.max_iterations, it.solver.max_iterations);
    EXPECT_EQ(s.solver.iteration_budget, it.solver.iteration_budget);
    EXPECT_EQ(s.solver.refactor_iterations, it.solver.refactor_iterations);
    // PcgJacobi is type pcg with preconditioner jacobi
    EXPECT_EQ(it.solver.kind, integrate::LinearSolverKind::PcgJacobi);
    EXPECT_EQ(s.solver.type, SolverType::Pcg);
    EXPECT_EQ(s.solver.preconditioner, Preconditioner::Jacobi);
    const solve::AmgOptions amg;
    EXPECT_EQ(s.solver.amg_strong_threshold, amg.strong_threshold);
    EXPECT_EQ(s.solver.amg_interpolation_max_elements, amg.interpolation_max_elements);
    EXPECT_EQ(s.solver.amg_max_coarse_size, amg.max_coarse_size);
    // the documented exception: a scene sets AMG up on a worker thread, a bare solver does not
    EXPECT_EQ(amg.background_solves, 0);
    EXPECT_EQ(s.solver.amg_background_solves, 8);
}

TEST(SceneDocs, AnUnknownNameSaysWhereAndWhatIsAccepted) {
    try {
        parse_scene(R"({"name": "d", "geometry": {"type": "box", "size": [0.1, 0.1, 0.1]},
            "material": {"youngs_modulus": 1e4}, "solver": {"preconditioner": "ilu"}})");
        FAIL() << "accepted an unknown preconditioner";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.where(), "/solver/preconditioner");
        for (const char* n : { "jacobi", "block_jacobi", "cell_block_jacobi", "lagged_cholesky",
                 "amg", "two_level", "ilu" })
            EXPECT_NE(e.problem().find(n), std::string::npos) << e.problem();
    }
    // main's two-level preconditioner (docs/decisions/0024) is a name of the same table
    const Scene two = parse_scene(R"({"name": "d", "geometry": {"type": "box",
        "size": [0.1, 0.1, 0.1]}, "material": {"youngs_modulus": 1e4},
        "solver": {"preconditioner": "two_level"}})");
    EXPECT_EQ(two.solver.preconditioner, Preconditioner::TwoLevel);
    EXPECT_STREQ(to_string(two.solver.preconditioner), "two_level");
    // every enum's names round-trip through to_string
    for (auto m : { Method::Tet, Method::Hex, Method::Mvc, Method::Harmonic, Method::Dg })
        EXPECT_STRNE(to_string(m), "?");
    for (auto v : { basis::VolumetricRule::Full, basis::VolumetricRule::MeanDilatation,
             basis::VolumetricRule::NodalAverage })
        EXPECT_STRNE(to_string(v), "?");
}

namespace {
/// The names of `table` that docs/scenes.md never spells as "name" or `name`.
template <class E, std::size_t N>
std::vector<std::string> undocumented(const detail::Name<E> (&table)[N], const std::string& doc) {
    std::vector<std::string> out;
    for (const detail::Name<E>& n : table) {
        const std::string name = n.text;
        if (doc.find('"' + name + '"') == std::string::npos
            && doc.find('`' + name + '`') == std::string::npos)
            out.push_back(name);
    }
    return out;
}
} // namespace

TEST(SceneDocs, EveryAcceptedNameIsDocumented) {
    // The parser accepts exactly the names of these tables; a name added to one (as main's
    // "two_level" was) must reach the reference too.
    std::ifstream in(std::string(POLYCUT_SOURCE_DIR) + "/docs/scenes.md");
    ASSERT_TRUE(in);
    std::stringstream text;
    text << in.rdbuf();
    const std::string doc = text.str();
    using namespace detail;
    using Missing = std::vector<std::string>;
    EXPECT_EQ(undocumented(kGeometryKind, doc), Missing {});
    EXPECT_EQ(undocumented(kObstacleKind, doc), Missing {});
    EXPECT_EQ(undocumented(kMethod, doc), Missing {});
    EXPECT_EQ(undocumented(kElements, doc), Missing {});
    EXPECT_EQ(undocumented(kTetSplit, doc), Missing {});
    EXPECT_EQ(undocumented(kImplicitShape, doc), Missing {});
    EXPECT_EQ(undocumented(kHullShape, doc), Missing {});
    EXPECT_EQ(undocumented(kNodeOrder, doc), Missing {});
    EXPECT_EQ(undocumented(kRepair, doc), Missing {});
    EXPECT_EQ(undocumented(kComponents, doc), Missing {});
    EXPECT_EQ(undocumented(kOctreeObject, doc), Missing {});
    EXPECT_EQ(undocumented(kOctreeKeep, doc), Missing {});
    EXPECT_EQ(undocumented(kSolverType, doc), Missing {});
    EXPECT_EQ(undocumented(kPreconditioner, doc), Missing {});
    EXPECT_EQ(undocumented(kWarmStart, doc), Missing {});
    EXPECT_EQ(undocumented(kDistribution, doc), Missing {});
    EXPECT_EQ(undocumented(kCutMethod, doc), Missing {});
    EXPECT_EQ(undocumented(kToolShape, doc), Missing {});
    EXPECT_EQ(undocumented(kPolyRule, doc), Missing {});
    EXPECT_EQ(undocumented(kVolumetric, doc), Missing {});
    EXPECT_EQ(undocumented(kFlux, doc), Missing {});
    EXPECT_EQ(undocumented(kLambdaPenalty, doc), Missing {});
    EXPECT_EQ(undocumented(kIntegrator, doc), Missing {});
    EXPECT_EQ(undocumented(kStaticMode, doc), Missing {});
    // and the check can fail: a name the doc does not have is reported
    constexpr detail::Name<CutMethod> kMade[] = { { "no_such_cutter", CutMethod::Split } };
    EXPECT_EQ(undocumented(kMade, doc), Missing { "no_such_cutter" });
}

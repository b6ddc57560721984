// The volume mesh readers reject each kind of malformed file (issue 2 item 7) with a FileError
// naming the file, the line and the problem, and never crash on corrupted samples.
#include "io_test_util.hpp"
#include "polycut/common/error.hpp"
#include "polycut/mesh/io.hpp"
#include "polycut/mesh/validate.hpp"

#include <gtest/gtest.h>
#include <sstream>

using namespace polycut;
using namespace polycut::mesh;
namespace fs = std::filesystem;
using namespace polycut::test;

namespace {
/// A malformed file (or pair of files), the file and line the error must name, and a piece of
/// its message.
struct BadFile {
    std::string name;
    std::vector<std::pair<std::string, std::string>> files; ///< file name, content
    std::string read; ///< the path given to the reader
    std::string error_file; ///< the file the error names
    long line;
    std::string message;
};

void expect_rejected(const BadFile& bad) {
    SCOPED_TRACE(bad.name);
    const fs::path dir = test_dir() / bad.name;
    fs::create_directories(dir);
    for (const auto& [file, text] : bad.files)
        write_text(dir / file, text);
    try {
        const Mesh m = read_volume_mesh((dir / bad.read).string());
        ADD_FAILURE() << "accepted, " << m.num_cells() << " cells";
    } catch (const FileError& e) {
        EXPECT_EQ(e.path(), (dir / bad.error_file).string()) << e.what();
        EXPECT_EQ(e.line(), bad.line) << e.what();
        EXPECT_NE(std::string(e.what()).find(bad.message), std::string::npos)
            << "message: " << e.what() << "\nexpected to contain: " << bad.message;
        // The location is part of the text a user sees.
        if (bad.line > 0) {
            EXPECT_NE(std::string(e.what()).find(bad.error_file + ":" + std::to_string(bad.line)),
                std::string::npos)
                << e.what();
        }
    } catch (const std::exception& e) {
        ADD_FAILURE() << "threw something other than FileError: " << e.what();
    }
}

const std::string kV2Header = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
/// Nodes of a unit tet with tags 1..4 (lines 4-10 after kV2Header).
const std::string kV2UnitTetNodes = "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n";
const std::string kV41Header = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
const std::string kV41UnitTetNodes
    = "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n";

const std::string kCubeNode = "8 3 0 0\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n"
                              "5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n";
const std::string kCubeEle = "6 4 0\n1 1 2 3 7\n2 1 3 4 7\n3 1 4 8 7\n4 1 8 5 7\n5 1 5 6 7\n"
                             "6 1 6 2 7\n";
} // namespace

// ---- readers: malformed files ----

TEST(ReadGmsh, RejectsMalformedFiles) {
    const std::string tet_v2 = kV2Header + kV2UnitTetNodes; // 10 lines
    const std::vector<BadFile> cases {
        { "missing", {}, "none.msh", "none.msh", 0, "cannot open file" },
        { "empty", { { "a.msh", "" } }, "a.msh", "a.msh", 0, "no $MeshFormat" },
        { "not_a_section", { { "a.msh", kV2Header + "hello\n" } }, "a.msh", "a.msh", 4,
            "expected a section header" },
        { "version_3", { { "a.msh", "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n" } }, "a.msh", "a.msh",
            2, "unsupported .msh format version 3.0" },
        { "version_1", { { "a.msh", "$NOD\n1\n1 0 0 0\n$ENDNOD\n" } }, "a.msh", "a.msh", 1,
            "gmsh format 1" },
        { "binary", { { "a.msh", "$MeshFormat\n4.1 1 8\n\x01\n$EndMeshFormat\n" } }, "a.msh",
            "a.msh", 2, "binary .msh files are not supported" },
        { "truncated_nodes", { { "a.msh", kV2Header + "$Nodes\n4\n1 0 0 0\n2 1 0 0\n" } }, "a.msh",
            "a.msh", 7, "unexpected end of file in $Nodes after 2 of 4 nodes" },
        { "count_too_large",
            { { "a.msh",
                kV2Header + "$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n" } },
            "a.msh", "a.msh", 10, "$Nodes ends after 4 of 5 nodes" },
        { "count_too_small",
            { { "a.msh",
                kV2Header + "$Nodes\n3\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n" } },
            "a.msh", "a.msh", 9, "expected $EndNodes, found '4 0 0 1'" },
        { "non_numeric", { { "a.msh", kV2Header + "$Nodes\n2\n1 0 0 0\n2 1 abc 0\n$EndNodes\n" } },
            "a.msh", "a.msh", 7, "y coordinate 'abc' is not a number" },
        { "nan", { { "a.msh", kV2Header + "$Nodes\n2\n1 0 0 0\n2 1 nan 0\n$EndNodes\n" } }, "a.msh",
            "a.msh", 7, "y coordinate 'nan' is not finite" },
        { "inf", { { "a.msh", kV2Header + "$Nodes\n2\n1 0 0 -inf\n2 1 0 0\n$EndNodes\n" } },
            "a.msh", "a.msh", 6, "z coordinate '-inf' is not finite" },
        { "missing_coordinate", { { "a.msh", kV2Header + "$Nodes\n1\n1 0 0\n$EndNodes\n" } },
            "a.msh", "a.msh", 6, "expected 4 values, found 3" },
        { "unknown_node", { { "a.msh", tet_v2 + "$Elements\n1\n1 4 0 1 2 3 99\n$EndElements\n" } },
            "a.msh", "a.msh", 13, "node tag 99 is not in $Nodes" },
        { "zero_volume_tet",
            { { "a.msh",
                kV2Header + "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n$EndNodes\n"
                    + "$Elements\n2\n1 15 0 1\n2 4 2 0 1 1 2 3 4\n$EndElements\n" } },
            "a.msh", "a.msh", 14, "zero-volume tetrahedron" },
        { "repeated_node", { { "a.msh", tet_v2 + "$Elements\n1\n1 4 0 1 2 3 3\n$EndElements\n" } },
            "a.msh", "a.msh", 13, "tetrahedron repeats a node" },
        { "duplicate_element",
            { { "a.msh", tet_v2 + "$Elements\n2\n1 4 0 1 2 3 4\n2 4 0 4 3 2 1\n$EndElements\n" } },
            "a.msh", "a.msh", 14, "element repeats the element on line 13" },
        { "prism", { { "a.msh", tet_v2 + "$Elements\n1\n1 6 0 1 2 3 4 1 2\n$EndElements\n" } },
            "a.msh", "a.msh", 13, "element type 6 (6-node prism) is not supported" },
        { "unknown_type", { { "a.msh", tet_v2 + "$Elements\n1\n1 99 0 1 2 3 4\n$EndElements\n" } },
            "a.msh", "a.msh", 13, "unknown element type 99" },
        { "wrong_node_count", { { "a.msh", tet_v2 + "$Elements\n1\n1 4 0 1 2 3\n$EndElements\n" } },
            "a.msh", "a.msh", 13, "expected 7 values, found 6" },
        { "elements_before_nodes",
            { { "a.msh", kV2Header + "$Elements\n1\n1 4 0 1 2 3 4\n$EndElements\n" } }, "a.msh",
            "a.msh", 4, "$Elements before $Nodes" },
        { "repeated_tag", { { "a.msh", kV2Header + "$Nodes\n2\n1 0 0 0\n1 1 0 0\n$EndNodes\n" } },
            "a.msh", "a.msh", 7, "node tag 1 repeats the node on line 6" },
        { "coincident_nodes",
            { { "a.msh",
                kV2Header + "$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
                    + "5 1 0 0\n6 2 0 0\n7 1 1 0\n8 1 0 1\n$EndNodes\n"
                    + "$Elements\n2\n1 4 0 1 2 3 4\n2 4 0 5 6 7 8\n$EndElements\n" } },
            "a.msh", "a.msh", 10, "node coincides with the node on line 7" },
        { "inverted_hex",
            { { "a.msh",
                kV2Header + "$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n"
                    + "5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n$EndNodes\n"
                    + "$Elements\n1\n1 5 0 5 6 7 8 1 2 3 4\n$EndElements\n" } },
            "a.msh", "a.msh", 17, "inverted hexahedron" },
        { "no_elements", { { "a.msh", tet_v2 } }, "a.msh", "a.msh", 0, "no $Elements section" },
        { "only_surface", { { "a.msh", tet_v2 + "$Elements\n1\n1 2 0 1 2 3\n$EndElements\n" } },
            "a.msh", "a.msh", 0, "no tetrahedra or hexahedra" },
        { "unclosed_section", { { "a.msh", kV2Header + "$Comments\nhello\n" } }, "a.msh", "a.msh",
            5, "missing $EndComments" },
        // Format 4.1.
        { "v41_node_total",
            { { "a.msh",
                kV41Header + "$Nodes\n1 5 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                    + "$EndNodes\n" } },
            "a.msh", "a.msh", 5, "$Nodes header says 5 nodes but its blocks hold 4" },
        { "v41_truncated_block",
            { { "a.msh", kV41Header + "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n" } },
            "a.msh", "a.msh", 12,
            "unexpected end of file in $Nodes after 2 of 4 node coordinates" },
        { "v41_element_block_short",
            { { "a.msh",
                kV41Header + kV41UnitTetNodes
                    + "$Elements\n1 2 1 2\n3 1 4 2\n1 1 2 3 4\n$EndElements\n" } },
            "a.msh", "a.msh", 20, "$Elements ends after 1 of 2 elements of the block" },
        { "v41_bad_element",
            { { "a.msh",
                kV41Header + kV41UnitTetNodes
                    + "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 x\n$EndElements\n" } },
            "a.msh", "a.msh", 19, "node tag 'x' is not an integer" },
        { "v41_unknown_node",
            { { "a.msh",
                kV41Header + kV41UnitTetNodes
                    + "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 5\n$EndElements\n" } },
            "a.msh", "a.msh", 19, "node tag 5 is not in $Nodes" },
        { "v40", { { "a.msh", "$MeshFormat\n4 0 8\n$EndMeshFormat\n" } }, "a.msh", "a.msh", 2,
            "unsupported .msh format version 4" },
    };
    for (const BadFile& bad : cases)
        expect_rejected(bad);
}

TEST(ReadTetgen, RejectsMalformedFiles) {
    const std::vector<BadFile> cases {
        { "missing_node", { { "a.ele", kCubeEle } }, "a.ele", "a.node", 0, "cannot open file" },
        { "missing_ele", { { "a.node", kCubeNode } }, "a.node", "a.ele", 0, "cannot open file" },
        { "dimension", { { "a.node", "8 2 0 0\n" }, { "a.ele", kCubeEle } }, "a.node", "a.node", 1,
            "dimension 2 is not supported" },
        { "header", { { "a.node", "8 3 0\n" }, { "a.ele", kCubeEle } }, "a.node", "a.node", 1,
            "expected 4 values, found 3" },
        { "first_index", { { "a.node", "1 3 0 0\n2 0 0 0\n" }, { "a.ele", kCubeEle } }, "a.node",
            "a.node", 2, "first point number is 2 (must be 0 or 1)" },
        { "sequence",
            { { "a.node", "# points\n3 3 0 0\n0 0 0 0\n1 1 0 0\n\n3 0 1 0\n" },
                { "a.ele", kCubeEle } },
            "a.node", "a.node", 6, "point number 3 out of sequence (expected 2)" },
        { "missing_marker", { { "a.node", "1 3 0 1\n1 0 0 0\n" }, { "a.ele", kCubeEle } }, "a.node",
            "a.node", 2, "point: expected 5 values, found 4" },
        { "inf_coordinate",
            { { "a.node", "2 3 0 0\n1 0 0 0\n2 inf 0 0  # far away\n" }, { "a.ele", kCubeEle } },
            "a.node", "a.node", 3, "x coordinate 'inf' is not finite" },
        { "extra_points", { { "a.node", "1 3 0 0\n1 0 0 0\n2 1 0 0\n" }, { "a.ele", kCubeEle } },
            "a.node", "a.node", 3, "extra data after 1 points" },
        { "node_out_of_range",
            { { "a.node", kCubeNode }, { "a.ele", "2 4 0\n1 1 2 3 7\n2 1 3 9 7\n" } }, "a.ele",
            "a.ele", 3, "node 9 is out of range [1, 8]" },
        { "truncated_ele",
            { { "a.node", kCubeNode }, { "a.ele", "3 4 0\n1 1 2 3 7\n2 1 3 4 7\n" } }, "a.node",
            "a.ele", 3, "unexpected end of file after 2 of 3 tetrahedra" },
        { "nodes_per_tet", { { "a.node", kCubeNode }, { "a.ele", "1 8 0\n" } }, "a.node", "a.ele",
            1, "nodes per tetrahedron must be 4 or 10, not 8" },
        { "non_numeric_node", { { "a.node", kCubeNode }, { "a.ele", "1 4 0\n1 1 2 three 7\n" } },
            "a.node", "a.ele", 2, "node 'three' is not an integer" },
        { "zero_volume",
            { { "a.node", kCubeNode }, { "a.ele", "2 4 0\n1 1 2 3 7\n2 1 2 3 4 # flat\n" } },
            "a.ele", "a.ele", 3, "zero-volume tetrahedron" },
        { "no_tets", { { "a.node", kCubeNode }, { "a.ele", "0 4 0\n" } }, "a.ele", "a.ele", 1,
            "no tetrahedra" },
        { "extension", { { "a.txt", "" } }, "a.txt", "a.txt", 0,
            "unknown volume mesh format '.txt'" },
    };
    for (const BadFile& bad : cases)
        expect_rejected(bad);
}
// ---- never a crash, never a half-built mesh ----

TEST(ReadVolumeMesh, CorruptedSamplesThrowFileErrorOrGiveValidMeshes) {
    // Every truncation of each sample, and each line with one token replaced by junk, must give
    // either a FileError or a mesh that passes validate() (e.g. a changed coordinate that keeps
    // the cells valid).
    const fs::path dir = test_dir();
    const std::vector<std::pair<std::string, std::string>> samples { { "blocks_v2.msh", "" },
        { "blocks_v41.msh", "" }, { "cube.node", "cube.ele" }, { "cube.ele", "cube.node" } };
    const std::vector<std::string> junk { "x", "-1", "1e999", "nan", "99999", "$Nodes", "0.5" };
    int cases = 0, accepted = 0;
    auto attempt = [&](const std::string& name, const std::string& text, const std::string& other) {
        const fs::path case_dir = dir / std::to_string(cases++);
        fs::create_directories(case_dir);
        write_text(case_dir / name, text);
        if (!other.empty())
            fs::copy_file(kData + other, case_dir / other);
        try {
            const Mesh m = read_volume_mesh((case_dir / name).string());
            EXPECT_NO_THROW(validate(m)) << case_dir;
            ++accepted;
        } catch (const FileError& e) {
            EXPECT_GE(e.line(), 0);
        } catch (const std::exception& e) {
            ADD_FAILURE() << case_dir << ": not a FileError: " << e.what();
        }
    };
    for (const auto& [name, other] : samples) {
        std::vector<std::string> lines;
        std::istringstream in(read_text(kData + name));
        for (std::string line; std::getline(in, line);)
            lines.push_back(line);
        for (std::size_t k = 0; k < lines.size(); ++k) {
            std::string head;
            for (std::size_t i = 0; i < k; ++i)
                head += lines[i] + "\n";
            attempt(name, head, other);
            std::istringstream tokens(lines[k]);
            std::vector<std::string> words;
            for (std::string w; tokens >> w;)
                words.push_back(w);
            for (std::size_t w = 0; w < words.size(); ++w) {
                const std::string& bad = junk[(k + w) % junk.size()];
                std::string text;
                for (std::size_t i = 0; i < lines.size(); ++i) {
                    if (i != k) {
                        text += lines[i] + "\n";
                        continue;
                    }
                    for (std::size_t v = 0; v < words.size(); ++v)
                        text += (v ? " " : "") + (v == w ? bad : words[v]);
                    text += "\n";
                }
                attempt(name, text, other);
            }
        }
    }
    EXPECT_GT(cases, 500);
    EXPECT_GT(accepted, 0); // some harmless edits (a changed attribute) must still read
}

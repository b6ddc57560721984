// gmsh .msh reader, ASCII formats 2.x and 4.1 (gmsh reference manual, sec. "MSH file format").
// Only what a volume mesh needs is read: $MeshFormat, $Nodes and $Elements; other sections are
// skipped up to their $End line. Every record is expected on its own line, as gmsh writes them.
#include "polycut/mesh/io_gmsh.hpp"

#include "io_build.hpp"
#include "io_text.hpp"

#include <cmath>
#include <unordered_map>

namespace polycut::mesh {
namespace {
constexpr long kMaxCount = std::numeric_limits<Index>::max() / 8;

struct ElementType {
    int type;
    int nodes;
    int dim;
    const char* name;
};

// gmsh element types (first-order and the common higher-order ones).
constexpr ElementType kElementTypes[] = { { 1, 2, 1, "2-node line" },
    { 2, 3, 2, "3-node triangle" }, { 3, 4, 2, "4-node quadrangle" },
    { 4, 4, 3, "4-node tetrahedron" }, { 5, 8, 3, "8-node hexahedron" },
    { 6, 6, 3, "6-node prism" }, { 7, 5, 3, "5-node pyramid" }, { 8, 3, 1, "3-node line" },
    { 9, 6, 2, "6-node triangle" }, { 10, 9, 2, "9-node quadrangle" },
    { 11, 10, 3, "10-node tetrahedron" }, { 12, 27, 3, "27-node hexahedron" },
    { 13, 18, 3, "18-node prism" }, { 14, 14, 3, "14-node pyramid" }, { 15, 1, 0, "1-node point" },
    { 16, 8, 2, "8-node quadrangle" }, { 17, 20, 3, "20-node hexahedron" },
    { 18, 15, 3, "15-node prism" }, { 19, 13, 3, "13-node pyramid" },
    { 20, 9, 2, "9-node triangle" }, { 21, 10, 2, "10-node triangle" }, { 26, 4, 1, "4-node line" },
    { 27, 5, 1, "5-node line" }, { 28, 6, 1, "6-node line" },
    { 29, 20, 3, "20-node tetrahedron" } };

const ElementType* find_type(long type) {
    for (const ElementType& t : kElementTypes)
        if (t.type == type)
            return &t;
    return nullptr;
}

class GmshReader {
public:
    explicit GmshReader(const std::string& path)
        : m_in(path) {
        m_raw.node_path = path;
        m_raw.element_path = path;
    }

    Mesh read() {
        while (m_in.next()) {
            const std::string_view head = m_in.tokens().front();
            if (m_in.size() != 1 || head.front() != '$')
                m_in.fail(
                    "expected a section header such as $Nodes, found " + io::quoted(m_in.text()));
            if (head == "$MeshFormat")
                read_format();
            else if (head == "$NOD" || head == "$ELM")
                m_in.fail("gmsh format 1 (" + std::string(head)
                    + ") is not supported; save as format 2.2 or 4.1");
            else if (head == "$Nodes")
                m_version == 2 ? read_nodes_v2() : read_nodes_v4();
            else if (head == "$Elements")
                m_version == 2 ? read_elements_v2() : read_elements_v4();
            else if (head.substr(0, 4) == "$End")
                m_in.fail(std::string(head) + " without a matching section start");
            else
                skip_section(head);
        }
        const std::string& path = m_in.path();
        if (m_version == 0)
            throw FileError(path, 0, "not a gmsh file: no $MeshFormat section");
        if (!m_have_nodes)
            throw FileError(path, 0, "no $Nodes section");
        if (!m_have_elements)
            throw FileError(path, 0, "no $Elements section");
        return io::build_mesh(m_raw);
    }

private:
    void read_format() {
        if (m_version != 0)
            m_in.fail("second $MeshFormat section");
        m_in.next_or_fail("in $MeshFormat");
        m_in.expect_tokens(3, "$MeshFormat (version, file type, data size)");
        const double version = m_in.real(0, "format version");
        const long file_type = m_in.integer(1, "file type", 0, 1);
        if (file_type == 1)
            m_in.fail("binary .msh files are not supported; save as ASCII (gmsh option "
                      "Mesh.Binary = 0)");
        if (version >= 2.0 && version < 3.0)
            m_version = 2;
        else if (version == 4.1)
            m_version = 4;
        else
            m_in.fail("unsupported .msh format version " + std::string(m_in.tokens()[0])
                + " (2.x and 4.1 are supported)");
        expect_end("$EndMeshFormat", "");
    }

    void expect_end(std::string_view end, const std::string& hint) {
        m_in.next_or_fail("(missing " + std::string(end) + ")");
        if (m_in.size() != 1 || m_in.tokens().front() != end)
            m_in.fail("expected " + std::string(end) + ", found " + io::quoted(m_in.text()) + hint);
    }

    /// Next record of a section: fails at the end of the file or at a `$` line.
    void next_record(const std::string& what, long i, long count, std::string_view section) {
        m_in.next_or_fail("in " + std::string(section) + " after " + std::to_string(i) + " of "
            + std::to_string(count) + " " + what + " (truncated file?)");
        if (m_in.tokens().front().front() == '$')
            m_in.fail(std::string(section) + " ends after " + std::to_string(i) + " of "
                + std::to_string(count) + " " + what + " (wrong count?)");
    }

    void skip_section(std::string_view head) {
        const std::string end = "$End" + std::string(head.substr(1));
        const std::string context = "in " + std::string(head) + " (missing " + end + ")";
        while (true) {
            m_in.next_or_fail(context);
            if (m_in.size() == 1 && m_in.tokens().front() == end)
                return;
        }
    }

    void start_nodes() {
        if (m_version == 0)
            m_in.fail("$Nodes before $MeshFormat");
        if (m_have_nodes)
            m_in.fail("second $Nodes section");
        m_have_nodes = true;
    }

    void add_node(long tag, const Vec3& x) {
        const auto [it, inserted] = m_node_of_tag.try_emplace(tag, Index(m_raw.nodes.size()));
        if (!inserted)
            m_in.fail("node tag " + std::to_string(tag) + " repeats the node on line "
                + std::to_string(m_raw.node_lines[std::size_t(it->second)]));
        m_raw.nodes.push_back(x);
        m_raw.node_lines.push_back(m_in.line());
    }

    Index node(std::size_t token) {
        const long tag = m_in.integer(token, "node tag");
        const auto it = m_node_of_tag.find(tag);
        if (it == m_node_of_tag.end())
            m_in.fail("node tag " + std::to_string(tag) + " is not in $Nodes");
        return it->second;
    }

    Vec3 coordinates() {
        return { m_in.real(0, "x coordinate"), m_in.real(1, "y coordinate"),
            m_in.real(2, "z coordinate") };
    }

    void start_elements() {
        if (!m_have_nodes)
            m_in.fail("$Elements before $Nodes");
        if (m_have_elements)
            m_in.fail("second $Elements section");
        m_have_elements = true;
    }

    /// Checks an element type; returns it, or fails for unknown and unsupported 3D types.
    const ElementType& element_type(std::size_t token) {
        const long type = m_in.integer(token, "element type");
        const ElementType* t = find_type(type);
        if (t == nullptr)
            m_in.fail("unknown element type " + std::to_string(type));
        if (t->dim == 3 && t->type != 4 && t->type != 5)
            m_in.fail("element type " + std::to_string(type) + " (" + t->name
                + ") is not supported; only 4-node tetrahedra (4) and 8-node hexahedra (5)");
        return *t;
    }

    void add_element(const ElementType& t, std::size_t first_node) {
        io::RawElement e;
        e.count = t.nodes;
        e.line = m_in.line();
        for (int k = 0; k < t.nodes; ++k)
            e.nodes[std::size_t(k)] = node(first_node + std::size_t(k));
        m_raw.elements.push_back(e);
    }

    // Format 2: $Nodes: n, then "tag x y z". $Elements: m, then
    // "tag type #tags tags... nodes...".
    void read_nodes_v2() {
        start_nodes();
        m_in.next_or_fail("in $Nodes");
        m_in.expect_tokens(1, "number of nodes");
        const long count = m_in.integer(0, "number of nodes", 0, kMaxCount);
        m_raw.nodes.reserve(std::size_t(std::min(count, 1L << 20)));
        for (long i = 0; i < count; ++i) {
            next_record("nodes", i, count, "$Nodes");
            m_in.expect_tokens(4, "node (tag x y z)");
            const long tag = m_in.integer(0, "node tag", 1);
            add_node(tag,
                { m_in.real(1, "x coordinate"), m_in.real(2, "y coordinate"),
                    m_in.real(3, "z coordinate") });
        }
        expect_end("$EndNodes", " (more nodes than the count " + std::to_string(count) + "?)");
    }

    void read_elements_v2() {
        start_elements();
        m_in.next_or_fail("in $Elements");
        m_in.expect_tokens(1, "number of elements");
        const long count = m_in.integer(0, "number of elements", 0, kMaxCount);
        for (long i = 0; i < count; ++i) {
            next_record("elements", i, count, "$Elements");
            m_in.expect_tokens(3, "element (tag type #tags ...)", true);
            m_in.integer(0, "element tag");
            const ElementType& t = element_type(1);
            const long num_tags = m_in.integer(2, "number of tags", 0, 1000);
            m_in.expect_tokens(std::size_t(3 + num_tags + t.nodes),
                std::string(t.name) + " with " + std::to_string(num_tags) + " tags");
            for (long k = 0; k < num_tags; ++k)
                m_in.integer(std::size_t(3 + k), "element tag value");
            if (t.dim == 3)
                add_element(t, std::size_t(3 + num_tags));
            else
                for (int k = 0; k < t.nodes; ++k)
                    node(std::size_t(3 + num_tags + k));
        }
        expect_end(
            "$EndElements", " (more elements than the count " + std::to_string(count) + "?)");
    }

    // Format 4.1: $Nodes: "#blocks #nodes minTag maxTag", per block "dim entity parametric
    // n", n tag lines, n coordinate lines. $Elements: "#blocks #elements minTag maxTag", per
    // block "dim entity type n", n lines "tag nodes...".
    void read_nodes_v4() {
        start_nodes();
        m_in.next_or_fail("in $Nodes");
        m_in.expect_tokens(4, "$Nodes header (#blocks #nodes minTag maxTag)");
        const long header_line = m_in.line();
        const long blocks = m_in.integer(0, "number of entity blocks", 0, kMaxCount);
        const long count = m_in.integer(1, "number of nodes", 0, kMaxCount);
        m_in.integer(2, "minimum node tag");
        m_in.integer(3, "maximum node tag");
        m_raw.nodes.reserve(std::size_t(std::min(count, 1L << 20)));
        long total = 0;
        std::vector<long> tags;
        for (long b = 0; b < blocks; ++b) {
            next_record("entity blocks", b, blocks, "$Nodes");
            m_in.expect_tokens(4, "node block header (dim entity parametric #nodes)");
            const long dim = m_in.integer(0, "entity dimension", 0, 3);
            m_in.integer(1, "entity tag");
            const long parametric = m_in.integer(2, "parametric flag", 0, 1);
            const long n = m_in.integer(3, "number of nodes in block", 0, kMaxCount);
            tags.clear();
            for (long i = 0; i < n; ++i) {
                next_record("node tags of the block", i, n, "$Nodes");
                m_in.expect_tokens(1, "node tag");
                tags.push_back(m_in.integer(0, "node tag", 1));
            }
            for (long i = 0; i < n; ++i) {
                next_record("node coordinates of the block", i, n, "$Nodes");
                m_in.expect_tokens(std::size_t(3 + (parametric ? dim : 0)), "node coordinates");
                add_node(tags[std::size_t(i)], coordinates());
            }
            total += n;
        }
        expect_end("$EndNodes", " (more entity blocks than the count?)");
        if (total != count)
            throw FileError(m_in.path(), header_line,
                "$Nodes header says " + std::to_string(count) + " nodes but its blocks hold "
                    + std::to_string(total));
    }

    void read_elements_v4() {
        start_elements();
        m_in.next_or_fail("in $Elements");
        m_in.expect_tokens(4, "$Elements header (#blocks #elements minTag maxTag)");
        const long header_line = m_in.line();
        const long blocks = m_in.integer(0, "number of entity blocks", 0, kMaxCount);
        const long count = m_in.integer(1, "number of elements", 0, kMaxCount);
        m_in.integer(2, "minimum element tag");
        m_in.integer(3, "maximum element tag");
        long total = 0;
        for (long b = 0; b < blocks; ++b) {
            next_record("entity blocks", b, blocks, "$Elements");
            m_in.expect_tokens(4, "element block header (dim entity type #elements)");
            m_in.integer(0, "entity dimension", 0, 3);
            m_in.integer(1, "entity tag");
            const ElementType& t = element_type(2);
            const long n = m_in.integer(3, "number of elements in block", 0, kMaxCount);
            for (long i = 0; i < n; ++i) {
                next_record("elements of the block", i, n, "$Elements");
                m_in.expect_tokens(1 + std::size_t(t.nodes),
                    std::string(t.name) + " (tag and " + std::to_string(t.nodes) + " nodes)");
                m_in.integer(0, "element tag");
                if (t.dim == 3)
                    add_element(t, 1);
                else
                    for (int k = 0; k < t.nodes; ++k)
                        node(1 + std::size_t(k));
            }
            total += n;
        }
        expect_end("$EndElements", " (more entity blocks than the count?)");
        if (total != count)
            throw FileError(m_in.path(), header_line,
                "$Elements header says " + std::to_string(count) + " elements but its blocks hold "
                    + std::to_string(total));
    }

    io::LineReader m_in;
    io::RawMesh m_raw;
    int m_version = 0; ///< 2 or 4 (4.1) once $MeshFormat is read
    bool m_have_nodes = false;
    bool m_have_elements = false;
    std::unordered_map<long, Index> m_node_of_tag;
};
} // namespace

Mesh read_gmsh(const std::string& path) {
    return GmshReader(path).read();
}

} // namespace polycut::mesh

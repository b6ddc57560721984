// Surface file readers: every format and encoding round-trips a closed surface with a known
// volume; malformed and hostile files (empty, garbage, truncated, NaN, ids out of range, huge
// declared counts) are refused with a FileError that names the file and the line or byte; and
// a fuzz loop over mutated bytes of valid files only ever loads or throws polycut::Error.
#include "polycut/common/error.hpp"
#include "polycut/meshing/surface.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <map>
#include <random>
#include <string>

using namespace polycut;
using namespace polycut::meshing;

namespace {

std::filesystem::path scratch() {
    static const std::filesystem::path dir = [] {
        auto d = std::filesystem::path(POLYCUT_BINARY_DIR) / "tests" / "meshing" / "scratch_io";
        std::filesystem::create_directories(d);
        return d;
    }();
    return dir;
}

std::string write_bytes(const std::string& name, const std::string& bytes) {
    const std::string path = (scratch() / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
}

std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    std::string bytes(std::size_t(in.tellg()), '\0');
    in.seekg(0);
    in.read(bytes.data(), std::streamsize(bytes.size()));
    return bytes;
}

/// The box [lo, hi] with each face split into n x n quads of two triangles, outward. With
/// dyadic coordinates every position is exact in float32 and the enclosed volume is exact.
SurfaceMesh box_surface(const Vec3& lo, const Vec3& hi, int n) {
    SurfaceMesh s;
    std::map<std::array<double, 3>, Index> ids;
    auto vertex = [&](const Vec3& p) {
        const auto [it, inserted] = ids.try_emplace({ p.x(), p.y(), p.z() }, Index(ids.size()));
        if (inserted)
            s.positions.push_back(p);
        return it->second;
    };
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
            // u x v = +e_a on the hi side, -e_a on the lo side.
            const int b = side ? (a + 1) % 3 : (a + 2) % 3;
            const int c = side ? (a + 2) % 3 : (a + 1) % 3;
            Vec3 origin = lo;
            origin[a] = side ? hi[a] : lo[a];
            Vec3 du = Vec3::Zero(), dv = Vec3::Zero();
            du[b] = (hi[b] - lo[b]) / n;
            dv[c] = (hi[c] - lo[c]) / n;
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    const Vec3 p = origin + i * du + j * dv;
                    const Index p00 = vertex(p), p10 = vertex(p + du), p11 = vertex(p + du + dv),
                                p01 = vertex(p + dv);
                    s.triangles.push_back({ p00, p10, p11 });
                    s.triangles.push_back({ p00, p11, p01 });
                }
        }
    return s;
}

const Vec3 kLo(-0.0625, -0.03125, 0), kHi(0.0625, 0.03125, 0.09375);
const double kBoxVolume = 0.125 * 0.0625 * 0.09375;

struct Encoding {
    const char* ext;
    SurfaceEncoding encoding;
    const char* name;
};
const Encoding kEncodings[] = {
    { ".off", SurfaceEncoding::Ascii, "off_ascii" },
    { ".off", SurfaceEncoding::Binary, "off_binary" },
    { ".obj", SurfaceEncoding::Ascii, "obj" },
    { ".stl", SurfaceEncoding::Ascii, "stl_ascii" },
    { ".stl", SurfaceEncoding::Binary, "stl_binary" },
    { ".ply", SurfaceEncoding::Ascii, "ply_ascii" },
    { ".ply", SurfaceEncoding::Binary, "ply_binary" },
};

/// Reads `path`, expecting a FileError that names it, whose problem contains `what` and
/// whose line is `line` (-1: any). Returns the message.
std::string expect_refused(const std::string& path, const std::string& what, long line = -1) {
    try {
        read_surface(path, false);
        ADD_FAILURE() << path << " was accepted";
    } catch (const FileError& e) {
        EXPECT_EQ(e.path(), path);
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(e.problem().find(what), std::string::npos)
            << "expected '" << what << "' in: " << e.what();
        if (line >= 0) {
            EXPECT_EQ(e.line(), line) << e.what();
        }
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << path << ": not a FileError: " << e.what();
    }
    return {};
}

/// Big-endian 32-bit integer bytes (binary OFF).
std::string be32(std::int32_t v) {
    std::string s(4, '\0');
    for (int k = 0; k < 4; ++k)
        s[std::size_t(k)] = char((std::uint32_t(v) >> (24 - 8 * k)) & 0xff);
    return s;
}
std::string le32(std::uint32_t v) {
    std::string s(4, '\0');
    for (int k = 0; k < 4; ++k)
        s[std::size_t(k)] = char((v >> (8 * k)) & 0xff);
    return s;
}
std::string be_float(float f) {
    return be32(std::bit_cast<std::int32_t>(f));
}

const std::string kPlyAsciiHeader = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                                    "property float y\nproperty float z\nelement face 4\n"
                                    "property list uchar int vertex_indices\nend_header\n";
const std::string kTetVertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
const std::string kTetFaces = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";

} // namespace

TEST(SurfaceIo, EveryFormatRoundTripsAClosedBox) {
    const SurfaceMesh box = box_surface(kLo, kHi, 4);
    ASSERT_EQ(box.triangles.size(), 6u * 32u);
    ASSERT_EQ(box.positions.size(), 6u * 16u + 2u);
    ASSERT_EQ(enclosed_volume(box), kBoxVolume);
    for (const Encoding& e : kEncodings) {
        const std::string path = (scratch() / (std::string("box_") + e.name + e.ext)).string();
        write_surface(path, box, e.encoding);
        const SurfaceMesh back = read_surface(path, true); // closed, oriented outward
        EXPECT_EQ(back.positions.size(), box.positions.size()) << e.name;
        EXPECT_EQ(back.triangles.size(), box.triangles.size()) << e.name;
        // Dyadic positions are exact in every encoding, float32 included.
        EXPECT_NEAR(enclosed_volume(back), kBoxVolume, 1e-9 * kBoxVolume) << e.name;
    }
}

// The shipped organ surface (non-dyadic coordinates): ASCII encodings carry 17 digits and give
// the positions back exactly; binary STL, OFF and float PLY round them to float32 (relative
// 6e-8), which moves the volume by ~1e-7.
TEST(SurfaceIo, OrganSurfaceRoundTrips) {
    const SurfaceMesh organ
        = read_surface(std::string(POLYCUT_SOURCE_DIR) + "/assets/meshes/liver_blob.off");
    const double V = enclosed_volume(organ);
    for (const Encoding& e : kEncodings) {
        const std::string path = (scratch() / (std::string("organ_") + e.name + e.ext)).string();
        write_surface(path, organ, e.encoding);
        const SurfaceMesh back = read_surface(path, true);
        ASSERT_EQ(back.triangles.size(), organ.triangles.size()) << e.name;
        const bool exact = e.encoding == SurfaceEncoding::Ascii || std::string(e.ext) == ".ply";
        EXPECT_NEAR(enclosed_volume(back), V, (exact ? 1e-12 : 1e-6) * V) << e.name;
    }
}

TEST(SurfaceIo, RefusesEmptyAndGarbageFiles) {
    for (const char* ext : { ".off", ".obj", ".stl", ".ply" }) {
        expect_refused(write_bytes(std::string("empty") + ext, ""), "empty file");
        expect_refused(write_bytes(std::string("garbage") + ext, "\x01\x02\xff garbage\n\x7f"), "");
    }
    expect_refused(write_bytes("surface.vtk", "x"), "unsupported surface format");
    expect_refused((scratch() / "missing.off").string(), "cannot open");
    expect_refused(write_bytes("g.off", "this is not an OFF file\n"), "is not OFF", 1);
    expect_refused(write_bytes("g.ply", "ply\nformat text 1.0\nend_header\n"), "format", 2);
    expect_refused(write_bytes("g.obj", "v 1 2 3\nbogus 1 2\n"), "unknown OBJ statement", 2);
    expect_refused(write_bytes("g.stl", "solid x\nfacet\nvertex 0 0 0\n"), "endfacet", 2);
}

TEST(SurfaceIo, RefusesTruncatedFilesInEveryFormat) {
    const SurfaceMesh box = box_surface(kLo, kHi, 1);
    for (const Encoding& e : kEncodings) {
        const std::string valid = (scratch() / (std::string("trunc_") + e.name + e.ext)).string();
        write_surface(valid, box, e.encoding);
        const std::string bytes = read_bytes(valid);
        // Cut in the middle of the data; OBJ is line-based and a cut there only loses lines,
        // so cut it inside a face line ("f 1" or less).
        const std::size_t cut
            = std::string(e.ext) == ".obj" ? bytes.rfind("\nf ") + 4 : bytes.size() / 2 + 1;
        const std::string path
            = write_bytes(std::string("truncated_") + e.name + e.ext, bytes.substr(0, cut));
        expect_refused(path, "");
    }
}

TEST(SurfaceIo, RefusesNonFiniteCoordinatesWithTheirPosition) {
    expect_refused(
        write_bytes("nan.off",
            "OFF\n4 4 0\n" + std::string("0 0 0\nnan 0 0\n") + "0 1 0\n0 0 1\n" + kTetFaces),
        "vertex 1: coordinate 'nan' is not a finite number", 4);
    expect_refused(write_bytes("inf.off",
                       "OFF\n# comment\n4 4 0\n1e999 0 0\n1 0 0\n0 1 0\n0 0 1\n" + kTetFaces),
        "not a finite number", 4);
    expect_refused(write_bytes("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n"),
        "coordinate 'inf' is not a finite number", 3);
    expect_refused(write_bytes("nan.stl",
                       "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 nan 0\n"
                       "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n"),
        "not a finite number", 5);
    expect_refused(
        write_bytes("nan.ply", kPlyAsciiHeader + "0 0 0\n1 0 0\n0 1 nan\n0 0 1\n" + kTetFaces),
        "is not a float", 12);
    // Binary: a NaN float in the second triangle of a binary STL, at byte 84 + 50 + 12 + 4.
    std::string stl(80, ' ');
    stl += le32(2);
    for (int t = 0; t < 2; ++t)
        stl += std::string(50, '\0');
    const float nan = std::nanf("");
    std::memcpy(stl.data() + 84 + 50 + 16, &nan, 4);
    expect_refused(write_bytes("nan_binary.stl", stl), "byte 150: triangle 1 has a non-finite");
    std::string off = "OFF BINARY\n" + be32(3) + be32(1) + be32(0);
    off += be_float(0) + be_float(0) + be_float(0) + be_float(1) + be_float(nan) + be_float(0);
    off += be_float(0) + be_float(1) + be_float(0);
    off += be32(3) + be32(0) + be32(1) + be32(2) + be32(0);
    expect_refused(write_bytes("nan_binary.off", off), "byte 35: vertex 1 is not finite");
}

TEST(SurfaceIo, RefusesIdsOutOfRangeWithTheirPosition) {
    expect_refused(write_bytes("range.off",
                       "OFF\n4 4 0\n" + kTetVertices + "3 0 2 1\n3 0 1 7\n3 1 2 3\n" + "3 0 3 2\n"),
        "face 1: vertex id '7' is not an integer in [0, 4)", 8);
    expect_refused(write_bytes("negative.off", "OFF\n4 1 0\n" + kTetVertices + "3 0 -1 2\n"),
        "vertex id '-1'", 7);
    expect_refused(write_bytes("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n"),
        "vertex id 4 is out of range [1, 3]", 5);
    expect_refused(
        write_bytes("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), "OBJ ids start at 1", 4);
    expect_refused(
        write_bytes("relative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n"), "relative", 4);
    expect_refused(write_bytes("range.ply",
                       kPlyAsciiHeader + kTetVertices + "3 0 2 1\n3 0 1 3\n3 1 2 4\n3 0 3 2\n"),
        "vertex id 4 is out of range [0, 4)", 16);
    std::string off = "OFF BINARY\n" + be32(3) + be32(1) + be32(0);
    for (int k = 0; k < 9; ++k)
        off += be_float(float(k == 3 || k == 7));
    off += be32(3) + be32(0) + be32(1) + be32(3) + be32(0);
    expect_refused(write_bytes("range_binary.off", off), "byte 59: face 0 uses vertex 3");
    expect_refused(write_bytes("two.off", "OFF\n4 1 0\n" + kTetVertices + "2 0 1\n"),
        "vertex count '2' is not an integer in [3, 65536]", 7);
}

TEST(SurfaceIo, RefusesHugeDeclaredCountsWithoutAllocating) {
    expect_refused(write_bytes("huge_vertices.off", "OFF\n2000000000 4 0\n" + kTetVertices),
        "declares 2000000000 vertices", 2);
    expect_refused(
        write_bytes("huge_polygon.off", "OFF\n4 1 0\n" + kTetVertices + "2000000000 0 1 2\n"),
        "vertex count '2000000000'", 7);
    expect_refused(write_bytes("many_ids.off", "OFF\n4 1 0\n" + kTetVertices + "60000 0 1 2\n"),
        "declares 60000 vertices but lists 3", 7);
    std::string off = "OFF BINARY\n" + be32(0x7fffffff) + be32(0x7fffffff) + be32(0);
    expect_refused(write_bytes("huge_binary.off", off), "more than the 0 bytes");
    std::string off_face = "OFF BINARY\n" + be32(3) + be32(1) + be32(0);
    for (int k = 0; k < 9; ++k)
        off_face += be_float(0);
    off_face += be32(1 << 30) + be32(0) + be32(1) + be32(2) + be32(0);
    expect_refused(write_bytes("huge_binary_face.off", off_face), "declares 1073741824 vertices");
    std::string stl(80, ' ');
    stl += le32(4000000000u) + std::string(50, '\0');
    expect_refused(write_bytes("huge.stl", stl), "binary STL declares 4000000000 triangles");
    expect_refused(write_bytes("huge.ply",
                       "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\n"
                       "property float y\nproperty float z\nelement face 1\n"
                       "property list uint int vertex_indices\nend_header\n0 0 0\n"),
        "declares 4000000000 items", 3);
    expect_refused(write_bytes("huge_list.ply",
                       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                       "property float y\nproperty float z\nelement face 1\n"
                       "property list uint int vertex_indices\nend_header\n0 0 0\n1 0 0\n"
                       "0 1 0\n4000000000 0 1 2\n"),
        "declares 4000000000 items", 13);
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                      "property float y\nproperty float z\nelement face 1\n"
                      "property list uint int vertex_indices\nend_header\n";
    ply += std::string(36, '\0') + le32(0xfffffff0u) + le32(0) + le32(1) + le32(2);
    expect_refused(write_bytes("huge_list_binary.ply", ply), "declares 4294967280 items");
}

// Files CGAL's reader would misread or crash on are refused by the scan.
TEST(SurfaceIo, RefusesLayoutsCgalMisreads) {
    expect_refused(write_bytes("int_coords.ply",
                       "ply\nformat ascii 1.0\nelement vertex 4\nproperty int x\nproperty int y\n"
                       "property int z\nelement face 4\nproperty list uchar int vertex_indices\n"
                       "end_header\n"
                           + kTetVertices + kTetFaces),
        "vertex coordinate x must be float or double", 4);
    expect_refused(write_bytes("orphan.ply", "ply\nformat ascii 1.0\nproperty float x\n"),
        "property before any element", 3);
    expect_refused(write_bytes("ushort_ids.ply",
                       "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                       "property float y\nproperty float z\nelement face 4\n"
                       "property list uchar ushort vertex_indices\nend_header\n"
                           + kTetVertices + kTetFaces),
        "items must be int or uint", 8);
    expect_refused(write_bytes("empty_element.ply",
                       "ply\nformat ascii 1.0\nelement junk 1000000000\nend_header\n"),
        "has no properties", 3);
    expect_refused(write_bytes("noc.off", "4OFF\n"), "is not OFF", 1);
}

// A tiny tet in ASCII PLY and OFF with comments and CRLF line ends is read.
TEST(SurfaceIo, ReadsCommentsAndCrlf) {
    std::string off = "# a comment\r\nOFF\r\n# counts next\r\n4 4 0\r\n" + kTetVertices + kTetFaces;
    std::string crlf;
    for (char c : off) {
        if (c == '\n' && (crlf.empty() || crlf.back() != '\r'))
            crlf += '\r';
        crlf += c;
    }
    const SurfaceMesh s = read_surface(write_bytes("crlf.off", crlf));
    EXPECT_NEAR(enclosed_volume(s), 1.0 / 6.0, 1e-15);
    const SurfaceMesh p = read_surface(write_bytes("tet.ply",
        "ply\nformat ascii 1.0\ncomment made by hand\n" + kPlyAsciiHeader.substr(21) + kTetVertices
            + kTetFaces));
    EXPECT_NEAR(enclosed_volume(p), 1.0 / 6.0, 1e-15);
}

// Mutated bytes of valid files (flips, random bytes, inserted digits, deleted and duplicated
// ranges, truncation), 300 per encoding: every read either loads or throws polycut::Error.
// POLYCUT_FUZZ_TRIALS and POLYCUT_FUZZ_SEED override the count and the seed (18) for a longer
// run, e.g. under the dev preset's sanitizers.
TEST(SurfaceIo, FuzzedFilesLoadOrThrowPolycutErrors) {
    const SurfaceMesh box = box_surface(kLo, kHi, 1);
    const char* trials_env = std::getenv("POLYCUT_FUZZ_TRIALS");
    const char* seed_env = std::getenv("POLYCUT_FUZZ_SEED");
    const int trials = trials_env ? std::atoi(trials_env) : 300;
    std::mt19937 rng(seed_env ? unsigned(std::atol(seed_env)) : 18u);
    int loaded = 0, refused = 0;
    for (const Encoding& e : kEncodings) {
        const std::string valid = (scratch() / (std::string("fuzz_") + e.name + e.ext)).string();
        write_surface(valid, box, e.encoding);
        const std::string original = read_bytes(valid);
        for (int trial = 0; trial < trials; ++trial) {
            std::string bytes = original;
            const int edits = 1 + int(rng() % 4);
            for (int k = 0; k < edits && !bytes.empty(); ++k) {
                const std::size_t at = rng() % bytes.size();
                const std::size_t len = 1 + rng() % std::min<std::size_t>(16, bytes.size() - at);
                switch (rng() % 6) {
                case 0:
                    bytes[at] = char(bytes[at] ^ (1 << (rng() % 8)));
                    break;
                case 1:
                    bytes[at] = char(rng() % 256);
                    break;
                case 2:
                    bytes.insert(at, std::string(1 + rng() % 12, char('0' + rng() % 10)));
                    break;
                case 3:
                    bytes.erase(at, len);
                    break;
                case 4:
                    bytes.insert(at, bytes.substr(at, len));
                    break;
                default:
                    bytes.resize(at);
                    break;
                }
            }
            const std::string path = write_bytes(std::string("fuzzed") + e.ext, bytes);
            try {
                const SurfaceMesh s = read_surface(path, false);
                ASSERT_FALSE(s.triangles.empty());
                ++loaded;
            } catch (const Error&) {
                ++refused;
            } catch (const std::exception& ex) {
                FAIL() << e.name << " trial " << trial << ": not a polycut::Error: " << ex.what();
            }
        }
    }
    std::printf("[ fuzz     ] %d mutated files loaded, %d refused\n", loaded, refused);
    EXPECT_GT(refused, 0);
    EXPECT_GT(loaded, 0);
}

// Vertices no face uses (found by tests/fuzz/fuzz_surface_readers: a PLY listing two tets'
// vertices but only the first tet's faces) used to become isolated vertices of the CGAL mesh,
// which the outward orientation read out of bounds (ASan: heap-use-after-free). They are
// dropped: the closed surface is the tet alone, with its exact volume.
TEST(SurfaceIo, UnusedVerticesAreDroppedFromAClosedSurface) {
    const std::string off
        = "OFF\n8 4 0\n" + kTetVertices + "5 5 5\n6 5 5\n5 6 5\n5 5 6\n" + kTetFaces;
    const SurfaceMesh s = read_surface(write_bytes("unused_vertices.off", off), true);
    EXPECT_EQ(s.positions.size(), 4u);
    ASSERT_EQ(s.triangles.size(), 4u);
    EXPECT_NEAR(enclosed_volume(s), 1.0 / 6.0, 1e-15);
    const SurfaceMesh soup = read_surface(write_bytes("unused_vertices_soup.off", off), false);
    EXPECT_EQ(soup.positions.size(), 8u); // without require_closed the file is returned as read
}

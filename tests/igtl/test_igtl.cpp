// polycut-igtl against a real polycut-server, through OpenIGTLink's own client (the library 3D
// Slicer's OpenIGTLinkIF is built on): the surface arrives as POLYDATA with the server's vertex
// and triangle counts and positions (in mm, to float precision), TRANSFORMs of a "scalpel"
// device cut (cells tagged 2 appear in the cut_tag scalar, the server's topology changes), and
// TRANSFORMs of another device grab and, when they stop, release.
#include "control_client.hpp"
#include "subprocess.hpp"

#include <algorithm>
#include <cmath>
#include <gtest/gtest.h>
#include <igtlClientSocket.h>
#include <igtlMessageHeader.h>
#include <igtlPolyDataMessage.h>
#include <igtlTransformMessage.h>
#include <nlohmann/json.hpp>
#include <thread>

namespace polycut {
namespace {

using json = nlohmann::json;
using record::test::Subprocess;
using namespace std::chrono_literals;

struct Polydata {
    std::vector<std::array<float, 3>> points; ///< [mm]
    std::size_t polygons = 0;
    std::vector<float> cut_tag; ///< per triangle
    std::vector<float> cut_tag_point; ///< per vertex
};

/// The next POLYDATA message from the socket (other types are skipped); nullopt on timeout.
std::optional<Polydata> next_polydata(igtl::ClientSocket& socket) {
    for (int skipped = 0; skipped < 100; ++skipped) {
        auto header = igtl::MessageHeader::New();
        header->InitPack();
        if (socket.Receive(header->GetPackPointer(), header->GetPackSize())
            != header->GetPackSize()) {
            return std::nullopt;
        }
        header->Unpack();
        if (std::string(header->GetDeviceType()) != "POLYDATA") {
            socket.Skip(header->GetBodySizeToRead(), 0);
            continue;
        }
        auto message = igtl::PolyDataMessage::New();
        message->SetMessageHeader(header);
        message->AllocatePack();
        socket.Receive(message->GetPackBodyPointer(), message->GetPackBodySize());
        EXPECT_TRUE(message->Unpack(1) & igtl::MessageHeader::UNPACK_BODY) << "CRC";
        Polydata out;
        auto points = message->GetPoints();
        for (int i = 0; i < points->GetNumberOfPoints(); ++i) {
            std::array<float, 3> p {};
            points->GetPoint(unsigned(i), p.data());
            out.points.push_back(p);
        }
        out.polygons = message->GetPolygons()->GetNumberOfCells();
        for (int a = 0; a < message->GetNumberOfAttributes(); ++a) {
            auto* attribute = message->GetAttribute(unsigned(a));
            std::vector<float> data(attribute->GetSize() * attribute->GetNumberOfComponents());
            attribute->GetData(data.data());
            const std::string name = attribute->GetName();
            if (name == "cut_tag") { // a cell scalar of 9 equal components (igtl_messages.cpp)
                EXPECT_EQ(attribute->GetType(), igtl::PolyDataAttribute::CELL_SCALAR);
                for (std::size_t c = 0; c < attribute->GetSize(); ++c) {
                    out.cut_tag.push_back(data[c * attribute->GetNumberOfComponents()]);
                }
            } else if (name == "cut_tag_point") {
                EXPECT_EQ(attribute->GetNumberOfComponents(), 1u);
                out.cut_tag_point = data;
            }
        }
        return out;
    }
    return std::nullopt;
}

/// A TRANSFORM named `device` with its origin at `origin_mm` and the identity rotation.
void send_pose(
    igtl::ClientSocket& socket, const char* device, const std::array<double, 3>& origin_mm) {
    igtl::Matrix4x4 m;
    igtl::IdentityMatrix(m);
    for (int r = 0; r < 3; ++r) {
        m[r][3] = float(origin_mm[r]);
    }
    auto message = igtl::TransformMessage::New();
    message->SetDeviceName(device);
    message->SetMatrix(m);
    message->Pack();
    ASSERT_EQ(socket.Send(message->GetPackPointer(), message->GetPackSize()), 1);
}

struct Session {
    std::unique_ptr<Subprocess> server, bridge;
    std::string control, stream;
    int port = 0;
};

/// polycut-server on `scene` (a file of assets/scenes), on free ports or the given endpoints.
std::unique_ptr<Subprocess> start_server(const std::string& scene, bool paused,
    const std::string& control = "tcp://127.0.0.1:*",
    const std::string& stream = "tcp://127.0.0.1:*") {
    std::vector<std::string> args = { POLYCUT_SERVER_EXE, "--scene",
        std::string(POLYCUT_SOURCE_DIR) + "/assets/scenes/" + scene, "--control", control,
        "--stream", stream, "--quiet" };
    if (paused) {
        args.push_back("--paused");
    }
    return std::make_unique<Subprocess>(args);
}

Session start(bool paused) {
    Session s;
    s.server = start_server("default.json", paused);
    const json ready = json::parse(s.server->read_line(60s).value());
    s.control = ready.at("control").get<std::string>();
    s.stream = ready.at("stream").get<std::string>();
    s.bridge = std::make_unique<Subprocess>(std::vector<std::string> { POLYCUT_IGTL_EXE, "--server",
        s.control, "--port", "0", "--rate", "50", "--idle", "0.3", "--quiet" });
    s.port = json::parse(s.bridge->read_line(30s).value()).at("port").get<int>();
    return s;
}

igtl::ClientSocket::Pointer connect(int port) {
    auto socket = igtl::ClientSocket::New();
    EXPECT_EQ(socket->ConnectToServer("127.0.0.1", port), 0);
    socket->SetReceiveTimeout(10000);
    return socket;
}

TEST(igtl, SendsTheSurfaceAsPolydataInMillimetres) {
    Session s = start(true); // paused: the surface holds still, so it can be compared exactly
    zmq::context_t context;
    record::ControlClient control(context, s.control);
    const auto snapshot
        = std::get<protocol::SurfaceSnapshot>(control.call(protocol::GetSurfaceParams {}));
    auto socket = connect(s.port);
    const auto polydata = next_polydata(*socket);
    ASSERT_TRUE(polydata);
    ASSERT_EQ(polydata->points.size(), snapshot.header.vertex_count);
    EXPECT_EQ(polydata->polygons, snapshot.header.triangle_count);
    ASSERT_EQ(polydata->cut_tag.size(), snapshot.header.triangle_count);
    // Every vertex at 1000 x its position in m, to float rounding (1e-4 mm at 100 mm).
    double worst = 0;
    for (std::size_t i = 0; i < polydata->points.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            worst = std::max(worst,
                std::abs(double(polydata->points[i][std::size_t(k)])
                    - 1000.0 * double(snapshot.positions[3 * i + std::size_t(k)])));
        }
    }
    EXPECT_LT(worst, 1e-4) << "mm";
    for (const float tag : polydata->cut_tag) {
        EXPECT_EQ(tag, 1.0f); // uncut: skin only
    }
    ASSERT_EQ(polydata->cut_tag_point.size(), snapshot.header.vertex_count);
    EXPECT_EQ(std::count(polydata->cut_tag_point.begin(), polydata->cut_tag_point.end(), 1.0f),
        long(snapshot.header.vertex_count));
    socket->CloseSocket();
}

TEST(igtl, ScalpelTransformsCutAndToolTransformsGrab) {
    Session s = start(false);
    zmq::context_t context;
    record::ControlClient control(context, s.control);
    auto socket = connect(s.port);
    ASSERT_TRUE(next_polydata(*socket));
    const auto before = std::get<protocol::Stats>(control.call(protocol::GetStatsParams {}));

    // A blade 30 mm long (from the tip up local z) drawn across the 10 x 10 x 5 cm block at
    // x = 3 mm, tip 10 mm above its base: a cut through the top 4 cm.
    for (int k = 0; k <= 14; ++k) {
        send_pose(*socket, "scalpel", { 3.0, -70.0 + 10.0 * k, 10.0 });
        std::this_thread::sleep_for(30ms);
    }
    long cut_cells = 0, cut_points = 0;
    for (int frames = 0; frames < 300 && cut_cells <= 10; ++frames) { // the cut spreads over ticks
        const auto polydata = next_polydata(*socket);
        ASSERT_TRUE(polydata);
        cut_cells = std::count(polydata->cut_tag.begin(), polydata->cut_tag.end(), 2.0f);
        cut_points
            = std::count(polydata->cut_tag_point.begin(), polydata->cut_tag_point.end(), 2.0f);
    }
    EXPECT_GT(cut_cells, 10) << "cut-tagged triangles in the POLYDATA";
    EXPECT_GT(cut_points, 10) << "vertices of cut triangles";
    const auto after = std::get<protocol::Stats>(control.call(protocol::GetStatsParams {}));
    EXPECT_GT(after.topology_version, before.topology_version);

    // Another device grabs the top near a corner and pulls it up; silence releases it.
    auto grabs = [&] {
        return std::get<protocol::Stats>(control.call(protocol::GetStatsParams {})).grabs;
    };
    long held = 0;
    for (int k = 0; k < 20 && held == 0; ++k) {
        send_pose(*socket, "forceps", { 30.0, 30.0, 50.0 + k });
        std::this_thread::sleep_for(50ms);
        held = long(grabs());
    }
    EXPECT_EQ(held, 1);
    long left = 1;
    for (int k = 0; k < 40 && left != 0; ++k) {
        std::this_thread::sleep_for(50ms);
        left = long(grabs());
    }
    EXPECT_EQ(left, 0) << "the grab is released once its TRANSFORMs stop";
    socket->CloseSocket();
}

TEST(igtl, FollowsARestartedServer) {
    Session s = start(false);
    auto socket = connect(s.port);
    const auto first = next_polydata(*socket);
    ASSERT_TRUE(first);
    // The server goes away and another one, on another scene, takes its endpoints.
    s.server->terminate();
    s.server = start_server("cut_halves.json", false, s.control, s.stream);
    ASSERT_TRUE(s.server->read_line(60s));
    zmq::context_t context;
    record::ControlClient control(context, s.control);
    const auto snapshot
        = std::get<protocol::SurfaceSnapshot>(control.call(protocol::GetSurfaceParams {}));
    ASSERT_NE(snapshot.header.vertex_count, first->points.size()) << "pick scenes that differ";
    bool followed = false;
    for (int frames = 0; frames < 500 && !followed; ++frames) {
        const auto polydata = next_polydata(*socket);
        ASSERT_TRUE(polydata) << "no POLYDATA after the restart";
        followed = polydata->points.size() == snapshot.header.vertex_count
            && polydata->polygons == snapshot.header.triangle_count;
    }
    EXPECT_TRUE(followed) << "the bridge still sends the old server's surface";
    socket->CloseSocket();
}

} // namespace
} // namespace polycut

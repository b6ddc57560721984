// Stream messages: surface frames (with and without topology) and events round-trip; malformed
// frames are rejected with a pointer.
#include "polycut/protocol/stream.hpp"

#include <cmath>
#include <gtest/gtest.h>

namespace polycut::protocol {
namespace {

SurfaceFrame tetra_surface(bool has_topology) {
    SurfaceFrame f;
    f.header.seq = 17;
    f.header.tick = 16;
    f.header.sim_time = 16.0 / 60.0;
    f.header.topology_version = 2;
    f.header.has_topology = has_topology;
    f.header.step = StepReport { 3.25, 7, 1.5e-9, { "clamped dt", "slow solve" } };
    f.header.applied = { std::int64_t { 4 }, std::string("cut-1") };
    f.positions = { 0, 0, 0, 0.1f, 0, 0, 0, 0.1f, 0, 0, 0, 0.1f };
    f.header.vertex_count = 4;
    f.header.triangle_count = 4;
    if (has_topology) {
        f.triangles = { 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3 };
        f.tags = { 1, 1, 2, 1 };
    }
    return f;
}

TEST(ProtocolStream, SurfaceWithTopologyRoundTrips) {
    const SurfaceFrame f = tetra_surface(true);
    const Message m = encode_surface(f.header, f.positions, f.triangles, f.tags);
    ASSERT_EQ(m.size(), 5u);
    EXPECT_EQ(m[0], "surface");
    EXPECT_EQ(m[2].size(), 4u * 3u * 4u);
    EXPECT_EQ(m[3].size(), 4u * 3u * 4u);
    EXPECT_EQ(m[4].size(), 4u);
    const auto d = decode_stream(m);
    ASSERT_TRUE(d.ok()) << d.error().pointer << ": " << d.error().reason;
    EXPECT_EQ(std::get<SurfaceFrame>(d.value()), f);
}

TEST(ProtocolStream, SurfaceWithoutTopologyCarriesPositionsOnly) {
    const SurfaceFrame f = tetra_surface(false);
    const Message m = encode_surface(f.header, f.positions, {}, {});
    ASSERT_EQ(m.size(), 3u);
    const auto d = decode_stream(m);
    ASSERT_TRUE(d.ok()) << d.error().reason;
    const auto& g = std::get<SurfaceFrame>(d.value());
    EXPECT_EQ(g, f);
    EXPECT_EQ(g.header.triangle_count, 4u); // count of the current topology, arrays not sent
}

TEST(ProtocolStream, NonFiniteResidualTravelsAsNull) {
    SurfaceFrame f = tetra_surface(false);
    f.header.step.residual = std::nan("");
    const Message m = encode_surface(f.header, f.positions, {}, {});
    EXPECT_NE(m[1].find(R"("residual":null)"), std::string::npos) << m[1];
    const auto d = decode_stream(m);
    ASSERT_TRUE(d.ok());
    EXPECT_TRUE(std::isnan(std::get<SurfaceFrame>(d.value()).header.step.residual));
}

TEST(ProtocolStream, EventRoundTrips) {
    const Event e { "topology", 120, 121, R"({"topology_version":3,"triangles":812})" };
    const Message m = encode_event(e);
    ASSERT_EQ(m.size(), 2u);
    EXPECT_EQ(m[0], "event");
    const auto d = decode_stream(m);
    ASSERT_TRUE(d.ok()) << d.error().reason;
    EXPECT_EQ(std::get<Event>(d.value()), e);
    // Invalid detail text becomes {}.
    const auto bad = decode_stream(encode_event(Event { "warning", 1, 0, "not json" }));
    ASSERT_TRUE(bad.ok());
    EXPECT_EQ(std::get<Event>(bad.value()).detail_json, "{}");
}

TEST(ProtocolStream, MalformedSurfaceFramesAreRejected) {
    const SurfaceFrame f = tetra_surface(true);
    const Message good = encode_surface(f.header, f.positions, f.triangles, f.tags);
    {
        Message m = good;
        m[3][0] = 9; // vertex index 9 >= 4 (little-endian low byte of triangles[0])
        const auto d = decode_stream(m);
        ASSERT_FALSE(d.ok());
        EXPECT_EQ(d.error().pointer, "/triangles/0/0");
    }
    {
        Message m = good;
        m[4][2] = 3; // tag 3
        const auto d = decode_stream(m);
        ASSERT_FALSE(d.ok());
        EXPECT_EQ(d.error().pointer, "/tags/2");
    }
    {
        Message m = good;
        m[2].pop_back(); // positions one byte short
        const auto d = decode_stream(m);
        ASSERT_FALSE(d.ok());
        EXPECT_EQ(d.error().pointer, "/positions");
    }
    {
        Message m = good;
        m.pop_back(); // tags frame missing
        const auto d = decode_stream(m);
        ASSERT_FALSE(d.ok());
        EXPECT_EQ(d.error().pointer, "/tags/$frame");
    }
    {
        Message m = good;
        m[0] = "surfac";
        EXPECT_FALSE(decode_stream(m).ok());
    }
}

} // namespace
} // namespace polycut::protocol

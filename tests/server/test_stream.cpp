// The surface stream: frames at the set rate with consecutive seq, topology arrays after a cut,
// late joiners rebuilding the exact surface from get_surface plus later frames (zguide Clone),
// and a subscriber that never reads not slowing the loop. Timing assertions are deliberately
// loose (factor 2): this box is shared and noisy; the measured distributions are printed.
#include "polycut/common/stats.hpp"
#include "server_fixture.hpp"

#include <iostream>

namespace polycut::server::testing {
namespace {

using namespace protocol;
using Clock = std::chrono::steady_clock;

class Stream : public ::testing::Test {
protected:
    SceneDir dir;
    zmq::context_t context { 1 };

    zmq::socket_t subscriber(const std::string& endpoint, std::string_view topic) {
        zmq::socket_t sub(context, zmq::socket_type::sub);
        sub.set(zmq::sockopt::linger, 0);
        sub.set(zmq::sockopt::rcvhwm, 10000);
        sub.connect(endpoint);
        sub.set(zmq::sockopt::subscribe, topic);
        return sub;
    }
};

/// Next decoded stream message, or nullopt on timeout.
std::optional<StreamMessage> next(zmq::socket_t& sub, int timeout_ms = 2000) {
    const auto frames = recv_message(sub, std::chrono::milliseconds(timeout_ms));
    if (!frames) {
        return std::nullopt;
    }
    auto decoded = decode_stream(*frames);
    EXPECT_TRUE(decoded.ok()) << (decoded.ok() ? "" : decoded.error().reason);
    if (!decoded) {
        return std::nullopt;
    }
    return decoded.value();
}

std::optional<SurfaceFrame> next_surface(zmq::socket_t& sub, int timeout_ms = 2000) {
    while (auto m = next(sub, timeout_ms)) {
        if (auto* s = std::get_if<SurfaceFrame>(&*m)) {
            return *s;
        }
    }
    return std::nullopt;
}

TEST_F(Stream, FramesArriveAtTheSetRateWithConsecutiveSeq) {
    ServerConfig config = test_config(dir, false);
    config.rate_hz = 50.0;
    RunningServer server(config);
    auto sub = subscriber(server.stream(), kSurfaceTopic);
    auto first = next_surface(sub, 5000);
    ASSERT_TRUE(first.has_value());
    std::vector<double> intervals_ms;
    std::uint64_t last_seq = first->header.seq;
    std::int64_t last_tick = first->header.tick;
    std::size_t gaps = 0, frames = 0;
    const auto start = Clock::now();
    auto last_time = start;
    while (Clock::now() - start < std::chrono::seconds(1)) {
        auto f = next_surface(sub, 1000);
        ASSERT_TRUE(f.has_value());
        const auto now = Clock::now();
        intervals_ms.push_back(std::chrono::duration<double, std::milli>(now - last_time).count());
        last_time = now;
        gaps += f->header.seq == last_seq + 1 ? 0 : 1;
        EXPECT_EQ(f->header.tick, last_tick + 1);
        last_seq = f->header.seq;
        last_tick = f->header.tick;
        ++frames;
    }
    const double seconds = std::chrono::duration<double>(last_time - start).count();
    const double rate = double(frames) / seconds;
    const Summary s = summarize(intervals_ms);
    std::cout << "[ stream ] set 50 Hz, measured " << rate << " Hz over " << frames
              << " frames; interval p50 " << s.median << " ms, p99 " << s.p99 << " ms, max "
              << s.max << " ms\n";
    EXPECT_EQ(gaps, 0u);
    EXPECT_GT(rate, 25.0);
    EXPECT_LT(rate, 100.0);
}

TEST_F(Stream, CutPublishesNewTopologyAndAnEvent) {
    RunningServer server(test_config(dir, true));
    Client client(context, server.control());
    auto sub = subscriber(server.stream(), "");
    // Wait until the subscription is in place (slow joiner): step until a frame arrives.
    std::optional<SurfaceFrame> before;
    for (int i = 0; i < 50 && !before; ++i) {
        client.ok<RunState>(StepParams { 1 });
        before = next_surface(sub, 100);
    }
    ASSERT_TRUE(before.has_value());
    while (next(sub, 100)) { } // drain
    const auto snap = client.ok<SurfaceSnapshot>(GetSurfaceParams {});

    const auto cut = client.call(CutParams { incision(0.003, -0.012, 0.012, 0.008) }, {},
        RequestId { std::string("cut-1") });
    ASSERT_TRUE(cut.ok());
    const auto& result = std::get<CutResult>(std::get<Result>(cut.outcome));
    client.ok<RunState>(StepParams { 1 });

    auto frame = next_surface(sub);
    ASSERT_TRUE(frame.has_value());
    EXPECT_EQ(frame->header.tick, result.tick);
    EXPECT_TRUE(frame->header.has_topology);
    EXPECT_EQ(frame->header.topology_version, result.topology_version);
    EXPECT_GT(frame->header.topology_version, snap.header.topology_version);
    ASSERT_EQ(frame->header.applied.size(), 1u);
    EXPECT_EQ(frame->header.applied[0], RequestId { std::string("cut-1") });
    // The cut added vertices and triangles, some tagged as cut surface.
    EXPECT_GT(frame->header.vertex_count, snap.header.vertex_count);
    EXPECT_NE(frame->triangles, snap.triangles);
    EXPECT_NE(std::count(frame->tags.begin(), frame->tags.end(), std::uint8_t(SurfaceTag::Cut)), 0);
    EXPECT_EQ(std::count(snap.tags.begin(), snap.tags.end(), std::uint8_t(SurfaceTag::Cut)), 0);
    // A topology event points at that frame.
    auto event = next(sub);
    ASSERT_TRUE(event.has_value());
    const auto* e = std::get_if<Event>(&*event);
    ASSERT_NE(e, nullptr);
    EXPECT_EQ(e->kind, "topology");
    EXPECT_EQ(e->seq, frame->header.seq);
    EXPECT_NE(e->detail_json.find("\"cut_ms\""), std::string::npos) << e->detail_json;
    EXPECT_NE(e->detail_json.find("\"request\":\"cut-1\""), std::string::npos) << e->detail_json;
    // The frame after carries positions only.
    client.ok<RunState>(StepParams { 1 });
    auto after = next_surface(sub);
    ASSERT_TRUE(after.has_value());
    EXPECT_FALSE(after->header.has_topology);
    EXPECT_TRUE(after->triangles.empty());
    EXPECT_EQ(after->header.triangle_count, frame->header.triangle_count);
}

/// A client-side mirror of the surface, following docs/protocol.md "Late joiners and gaps".
struct Mirror {
    SurfaceFrame surface;
    bool valid = false;
    std::size_t snapshots = 0;

    void snapshot(Client& client) {
        surface = client.ok<SurfaceSnapshot>(GetSurfaceParams {});
        valid = true;
        ++snapshots;
    }
    /// Applies a frame; false on a gap (the caller takes a new snapshot).
    bool apply(const SurfaceFrame& f) {
        if (f.header.seq <= surface.header.seq) {
            return true; // older than the snapshot
        }
        if (f.header.seq != surface.header.seq + 1
            || (f.header.topology_version != surface.header.topology_version
                && !f.header.has_topology)) {
            return false;
        }
        surface.header = f.header;
        surface.positions = f.positions;
        if (f.header.has_topology) {
            surface.triangles = f.triangles;
            surface.tags = f.tags;
        }
        return true;
    }
};

TEST_F(Stream, LateJoinerReconstructsTheExactSurface) {
    RunningServer server(test_config(dir, false));
    Client client(context, server.control());
    Client cutter(context, server.control());
    // The server has been running a while when the subscriber joins.
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    cutter.ok<CutResult>(CutParams { incision(0.003, -0.012, 0.012, 0.008) });

    auto sub = subscriber(server.stream(), kSurfaceTopic);
    std::this_thread::sleep_for(std::chrono::milliseconds(200)); // subscription in place
    Mirror mirror;
    mirror.snapshot(client);
    bool cut_done = false;
    const auto start = Clock::now();
    while (Clock::now() - start < std::chrono::milliseconds(800)) {
        auto f = next_surface(sub, 500);
        ASSERT_TRUE(f.has_value());
        if (!mirror.apply(*f)) {
            mirror.snapshot(client);
        }
        if (!cut_done && Clock::now() - start > std::chrono::milliseconds(300)) {
            cutter.ok<CutResult>(CutParams { incision(0.013, -0.012, 0.012, 0.008) });
            cut_done = true;
        }
    }
    const auto paused = client.ok<RunState>(PauseParams {});
    // Every frame up to the pause is published before the pause is answered.
    while (mirror.surface.header.tick < paused.tick) {
        auto f = next_surface(sub, 2000);
        ASSERT_TRUE(f.has_value());
        if (!mirror.apply(*f)) {
            mirror.snapshot(client);
        }
    }
    const auto truth = client.ok<SurfaceSnapshot>(GetSurfaceParams {});
    std::cout << "[ stream ] late joiner: " << mirror.snapshots << " snapshot(s), final seq "
              << truth.header.seq << "\n";
    EXPECT_EQ(mirror.surface.header.seq, truth.header.seq);
    EXPECT_EQ(mirror.surface.header.topology_version, truth.header.topology_version);
    EXPECT_EQ(mirror.surface.positions, truth.positions);
    EXPECT_EQ(mirror.surface.triangles, truth.triangles);
    EXPECT_EQ(mirror.surface.tags, truth.tags);
    EXPECT_GE(truth.header.topology_version, 3u); // both cuts are in it
}

TEST_F(Stream, StalledSubscriberDoesNotSlowTheLoop) {
    ServerConfig config = test_config(dir, false);
    config.rate_hz = 60.0;
    RunningServer server(config);
    Client client(context, server.control());
    // A subscriber that never reads, with the smallest buffers we can ask for.
    zmq::socket_t stalled(context, zmq::socket_type::sub);
    stalled.set(zmq::sockopt::linger, 0);
    stalled.set(zmq::sockopt::rcvhwm, 1);
    stalled.set(zmq::sockopt::rcvbuf, 4096);
    stalled.connect(server.stream());
    stalled.set(zmq::sockopt::subscribe, "");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto s0 = client.stats();
    const auto t0 = Clock::now();
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    const auto s1 = client.stats();
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    const double rate = double(s1.tick - s0.tick) / seconds;
    std::cout << "[ stream ] stalled subscriber: " << rate << " Hz (set 60), dropped "
              << s1.stream_dropped << ", over budget " << s1.ticks_over_budget << "\n";
    EXPECT_GT(rate, 30.0);
    EXPECT_LT(rate, 120.0);
}

} // namespace
} // namespace polycut::server::testing

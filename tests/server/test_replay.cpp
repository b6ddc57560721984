// Determinism: a session recorded with --record-commands and replayed on a fresh Session ends
// in the identical state (same state hash), whether the commands came while paused (step) or
// while running at real-time rate. Also unit tests of the session's own bookkeeping.
#include "polycut/common/error.hpp"
#include "server_command_log.hpp"
#include "server_fixture.hpp"

namespace polycut::server::testing {
namespace {

using namespace protocol;

class Replay : public ::testing::Test {
protected:
    SceneDir dir;
    zmq::context_t context { 1 };

    ReplaySummary replay(const std::string& log) {
        SessionConfig config;
        config.scene_dir = dir.path().string();
        Session session(config);
        return replay_command_log(log, session);
    }
};

std::string hex64(std::uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

/// A session touching every mutation: forces (one expiring), a grab moved and released, a cut
/// from a binary frame, a scalpel stroke, a reset and a scene load.
void drive(Client& client, bool paused) {
    auto pause_or_wait = [&](std::uint32_t ticks) {
        if (paused) {
            client.ok<RunState>(StepParams { ticks });
        } else {
            std::this_thread::sleep_for(std::chrono::milliseconds(15 * ticks));
        }
    };
    const auto f = client.ok<Created>(
        ApplyForceParams { { 0, 0, 0.02 }, { 0, 0.1, -0.3 }, 0.01, std::nullopt });
    client.ok<Created>(ApplyForceParams { { 0.01, 0, 0.02 }, { 0.1, 0, 0 }, 0.01, 0.05 });
    pause_or_wait(4);
    client.ok<CutResult>(
        CutParams { incision(0.003, -0.012, 0.012, 0.008) }, EncodeOptions { true });
    pause_or_wait(3);
    const auto g = client.ok<Created>(GrabParams { { 0.0, 0.005, 0.02 }, 400.0, 0.004 });
    for (int i = 1; i <= 3; ++i) {
        client.ok<Ack>(MoveGrabParams { g.id, { 0.0, 0.005 + 0.002 * i, 0.021 } });
        pause_or_wait(2);
    }
    client.ok<Ack>(ReleaseParams { g.id });
    client.ok<Ack>(RemoveForceParams { f.id });
    for (int i = 0; i < 4; ++i) {
        client.notify(ScalpelParams {
            9, { -0.012 + 0.008 * i, -0.007, 0.03 }, { -0.012 + 0.008 * i, -0.007, 0.012 } });
        pause_or_wait(1);
    }
    client.ok<CutResult>(EndStrokeParams { 9 });
    pause_or_wait(5);
}

TEST_F(Replay, PausedSessionReplaysToTheSameStateHash) {
    ServerConfig config = test_config(dir, true);
    const std::string log = dir.file("commands.jsonl");
    config.record_commands = log;
    std::string live_hash;
    std::int64_t live_tick = 0;
    {
        RunningServer server(config);
        Client client(context, server.control());
        drive(client, true);
        const Stats s = client.stats();
        live_hash = s.state_hash;
        live_tick = s.tick;
        EXPECT_EQ(s.open_strokes, 0u);
    }
    const ReplaySummary r = replay(log);
    EXPECT_EQ(r.rejected, 0u);
    EXPECT_EQ(r.tick, live_tick);
    EXPECT_EQ(hex64(r.state_hash), live_hash);
    EXPECT_GE(r.commands, 14u);
}

TEST_F(Replay, RunningSessionReplaysToTheSameStateHash) {
    ServerConfig config = test_config(dir, false);
    const std::string log = dir.file("commands.jsonl");
    config.record_commands = log;
    std::string live_hash;
    std::int64_t live_tick = 0;
    {
        RunningServer server(config);
        Client client(context, server.control());
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        drive(client, false);
        // Also a reset and a reload in the middle of a run.
        client.ok<RunState>(ResetParams {});
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        LoadSceneParams load;
        load.name = "small";
        client.ok<SceneResult>(load);
        client.ok<CutResult>(CutParams { incision(0.013, -0.012, 0.012, 0.008) });
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        client.ok<RunState>(PauseParams {});
        const Stats s = client.stats();
        live_hash = s.state_hash;
        live_tick = s.tick;
    }
    const ReplaySummary r = replay(log);
    EXPECT_EQ(r.rejected, 0u);
    EXPECT_EQ(r.tick, live_tick);
    EXPECT_EQ(hex64(r.state_hash), live_hash);
}

TEST_F(Replay, LargeBinaryCutReplays) {
    // A 2,000-triangle cut sent as a binary frame (~24 kB as float32) is logged as JSON (~390
    // kB, over the wire's 256 KiB JSON limit): the replay must still take it.
    ServerConfig config = test_config(dir, true);
    const std::string log = dir.file("commands.jsonl");
    config.record_commands = log;
    std::vector<Triangle3> strip;
    for (int k = 0; k < 1000; ++k) {
        const auto quad
            = incision(0.003, -0.012 + 0.024 * k / 1000, -0.012 + 0.024 * (k + 1) / 1000, 0.008);
        strip.insert(strip.end(), quad.begin(), quad.end());
    }
    std::string live_hash;
    std::int64_t live_tick = 0;
    {
        RunningServer server(config);
        Client client(context, server.control());
        client.ok<CutResult>(CutParams { strip }, EncodeOptions { true });
        client.ok<RunState>(StepParams { 130 }); // 16 triangles a tick: all of it cut
        const Stats s = client.stats();
        live_hash = s.state_hash;
        live_tick = s.tick;
    }
    EXPECT_GT(std::filesystem::file_size(log), std::uintmax_t(256u << 10));
    const ReplaySummary r = replay(log);
    EXPECT_EQ(r.rejected, 0u);
    EXPECT_EQ(r.tick, live_tick);
    EXPECT_EQ(hex64(r.state_hash), live_hash);
}

TEST(ReplayLog, MalformedLogsAreFileErrors) {
    const auto path = std::filesystem::temp_directory_path() / "polycut_bad_log.jsonl";
    std::ofstream(path) << "{\"polycut_command_log\":1,\"scene_file\":null}\nnot json\n";
    Session session;
    EXPECT_THROW(replay_command_log(path.string(), session), polycut::FileError);
    std::ofstream(path) << "{\"hello\":1}\n";
    EXPECT_THROW(replay_command_log(path.string(), session), polycut::FileError);
    std::filesystem::remove(path);
}

TEST(StrokeTableTest, BoundedPerClientAndExpired) {
    StrokeLimits limits;
    limits.max_per_client = 3;
    limits.max_total = 5;
    limits.idle_s = 10.0;
    StrokeTable table(limits);
    for (std::uint64_t s = 0; s < 5; ++s) {
        table.open("a", s, double(s));
    }
    EXPECT_EQ(table.size(), 3u); // the two oldest of client a went
    EXPECT_EQ(table.find("a", 0), nullptr);
    EXPECT_NE(table.find("a", 4), nullptr);
    for (std::uint64_t s = 0; s < 3; ++s) {
        table.open("b", s, 5.0 + double(s));
    }
    EXPECT_EQ(table.size(), 5u); // total bound
    table.expire(14.5); // a/2 (t=2), a/3 (t=3), a/4 (t=4) idle > 10 s
    EXPECT_EQ(table.size(), 3u);
    table.drop_client("b");
    EXPECT_EQ(table.size(), 0u);
}

TEST(ReplyCacheTest, BoundedPerClientAndByAge) {
    ReplyCacheLimits limits;
    limits.per_client = 2;
    limits.max_age_s = 5.0;
    ReplyCache cache(limits);
    cache.store("a", "1", Message { "r1" }, 0.0);
    cache.store("a", "2", Message { "r2" }, 1.0);
    cache.store("a", "3", Message { "r3" }, 2.0);
    EXPECT_EQ(cache.find("a", "1"), nullptr);
    ASSERT_NE(cache.find("a", "3"), nullptr);
    EXPECT_EQ(cache.find("a", "3")->front(), "r3");
    EXPECT_EQ(cache.find("b", "3"), nullptr);
    cache.expire(6.5); // r2 (t=1) is older than 5 s
    EXPECT_EQ(cache.size(), 1u);
    cache.expire(100.0);
    EXPECT_EQ(cache.size(), 0u);
}

} // namespace
} // namespace polycut::server::testing

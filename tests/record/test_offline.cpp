// Offline recording (command-log replay rendered tick by tick): frame counts, the mp4 path, run
// to run determinism (identical PNG bytes), and the cut colour appearing after a scripted cut
// and retraction but not before.
#include "offline_recorder.hpp"
#include "polycut/common/error.hpp"
#include "test_support.hpp"

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

namespace polycut::record {
namespace {

/// A 4 x 4 x 2 cm tet block fixed at its base (small: the test replays quickly).
constexpr const char* kScene = R"({
  "name": "record_test_block",
  "geometry": {"type": "box", "origin": [-0.02, -0.02, 0], "size": [0.04, 0.04, 0.02],
               "cells": [4, 4, 2], "elements": "tet"},
  "method": "tet",
  "material": {"youngs_modulus": 3e4, "poisson_ratio": 0.45, "density": 1000,
               "rayleigh_stiffness": 0.02},
  "integrator": {"type": "implicit_euler", "dt": 0.0166667, "corotated": true},
  "solver": {"type": "pcg", "preconditioner": "block_jacobi", "tolerance": 1e-6},
  "fixed": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1], "tolerance": 1e-9}}],
  "loads": {"gravity": [0, 0, -9.81]}
})";

/// The first tick whose frame shows the cut: commands logged at tick 4 act in tick 5.
constexpr int kCutTick = 5;
constexpr int kLastTick = 30;

/// A vertical cut at x = 5 mm through the top 14 mm, then a grab pulling the +x lip open.
constexpr const char* kLogBody = R"(
{"tick":4,"client":"74657374","request":{"jsonrpc":"2.0","id":1,"method":"cut","params":{"triangles":[[[0.005,-0.03,0.006],[0.005,0.03,0.006],[0.005,0.03,0.03]],[[0.005,-0.03,0.006],[0.005,0.03,0.03],[0.005,-0.03,0.03]]]}}}
{"tick":6,"client":"74657374","request":{"jsonrpc":"2.0","id":2,"method":"grab","params":{"point":[0.02,0,0.02],"radius":0.008,"stiffness":300}}}
{"tick":8,"client":"74657374","request":{"jsonrpc":"2.0","id":3,"method":"move_grab","params":{"id":1,"target":[0.03,0,0.024]}}}
{"tick":14,"client":"74657374","request":{"jsonrpc":"2.0","id":4,"method":"move_grab","params":{"id":1,"target":[0.04,0,0.026]}}}
{"tick":30,"end":true}
)";

struct Fixture {
    std::string scene;
    std::string log;
};

Fixture write_fixture(const std::string& dir) {
    Fixture f { dir + "/block.json", dir + "/session.jsonl" };
    std::ofstream(f.scene) << kScene;
    std::ofstream log(f.log);
    log << R"({"polycut_command_log":1,"scene_file":null,"scene_dir":")" << dir << "\"}";
    log << kLogBody;
    return f;
}

RecordRender small_render() {
    RecordRender r;
    r.width = 320;
    r.height = 240;
    r.msaa = 4;
    return r;
}

OfflineSummary record_pngs(const Fixture& f, const std::string& out, long every = 1) {
    OfflineOptions options;
    options.scene_file = f.scene;
    options.commands = f.log;
    options.every = every;
    options.progress = false;
    return record_offline(options, small_render(), [&](double) { return make_png_sink(out); });
}

class Offline : public ::testing::Test {
protected:
    void SetUp() override {
        if (!offline_available()) {
            GTEST_SKIP() << "built without the simulation";
        }
        m_dir = test::scratch_dir(::testing::UnitTest::GetInstance()->current_test_info()->name());
        m_fixture = write_fixture(m_dir);
    }
    std::string m_dir;
    Fixture m_fixture;
};

TEST_F(Offline, RendersEveryTickOfTheLogWithNoDrops) {
    const std::string out = m_dir + "/frames";
    const OfflineSummary s = record_pngs(m_fixture, out);
    EXPECT_EQ(s.ticks, kLastTick);
    EXPECT_EQ(s.frames, kLastTick);
    EXPECT_EQ(s.commands, 4u);
    EXPECT_EQ(s.rejected, 0u);
    EXPECT_NEAR(s.fps, 60.0, 0.01);
    for (long k = 0; k < kLastTick; ++k) {
        EXPECT_TRUE(std::filesystem::exists(out + "/" + png_frame_name(k))) << k;
    }
    EXPECT_FALSE(std::filesystem::exists(out + "/" + png_frame_name(kLastTick)));
}

TEST_F(Offline, EveryKthTickAndFrameLimit) {
    OfflineOptions options;
    options.scene_file = m_fixture.scene;
    options.commands = m_fixture.log;
    options.every = 3;
    options.max_frames = 4;
    options.progress = false;
    const std::string out = m_dir + "/frames";
    const OfflineSummary s
        = record_offline(options, small_render(), [&](double) { return make_png_sink(out); });
    EXPECT_EQ(s.frames, 4);
    EXPECT_EQ(s.ticks, 1 + 3 * 3); // ticks 1, 4, 7, 10
    EXPECT_NEAR(s.fps, 20.0, 0.01);
}

TEST_F(Offline, IsDeterministicToTheByte) {
    const OfflineSummary a = record_pngs(m_fixture, m_dir + "/a");
    const OfflineSummary b = record_pngs(m_fixture, m_dir + "/b");
    EXPECT_EQ(a.state_hash, b.state_hash);
    ASSERT_EQ(a.frames, b.frames);
    for (long k = 0; k < a.frames; ++k) {
        const std::string name = png_frame_name(k);
        const std::string bytes_a = test::read_bytes(m_dir + "/a/" + name);
        ASSERT_FALSE(bytes_a.empty());
        EXPECT_EQ(bytes_a, test::read_bytes(m_dir + "/b/" + name)) << name;
    }
}

TEST_F(Offline, CutColourAppearsAfterTheCutAndNotBefore) {
    const std::string out = m_dir + "/frames";
    const OfflineSummary s = record_pngs(m_fixture, out);
    ASSERT_EQ(s.frames, kLastTick);
    EXPECT_GT(s.topology_version, 0u);
    for (int tick = 1; tick < kCutTick; ++tick) {
        const render::Image before = render::read_png(out + "/" + png_frame_name(tick - 1));
        EXPECT_EQ(test::count_cut_pixels(before), 0) << "tick " << tick;
    }
    const render::Image last = render::read_png(out + "/" + png_frame_name(kLastTick - 1));
    // The retracted lip exposes the cut faces: at least 0.2 % of the image is cut-coloured.
    EXPECT_GT(test::count_cut_pixels(last), 320 * 240 / 500);
}

TEST_F(Offline, Mp4HasOneVideoFramePerRenderedTick) {
    if (find_executable("ffmpeg").empty() || find_executable("ffprobe").empty()) {
        GTEST_SKIP() << "ffmpeg/ffprobe not installed";
    }
    OfflineOptions options;
    options.scene_file = m_fixture.scene;
    options.commands = m_fixture.log;
    options.every = 2;
    options.progress = false;
    const std::string path = m_dir + "/session.mp4";
    const OfflineSummary s = record_offline(options, small_render(), [&](double fps) {
        Mp4Options mp4;
        mp4.path = path;
        mp4.width = 320;
        mp4.height = 240;
        mp4.fps = fps;
        return make_mp4_sink(mp4);
    });
    EXPECT_EQ(s.frames, kLastTick / 2);
    const auto info = test::probe_video(path);
    ASSERT_FALSE(info.empty());
    EXPECT_EQ(info.at("nb_read_frames"), std::to_string(kLastTick / 2));
    EXPECT_EQ(info.at("width"), "320");
    EXPECT_EQ(info.at("height"), "240");
}

TEST(OfflineErrors, BadInputIsATypedError) {
    if (!offline_available()) {
        GTEST_SKIP() << "built without the simulation";
    }
    const std::string dir = test::scratch_dir("offline_errors");
    const Fixture f = write_fixture(dir);
    OfflineOptions options;
    options.scene_file = dir + "/missing.json";
    options.commands = f.log;
    options.progress = false;
    const auto sink = [&](double) { return make_png_sink(dir + "/x"); };
    EXPECT_THROW(record_offline(options, small_render(), sink), FileError);
    options.scene_file = f.scene;
    std::ofstream(dir + "/bad.jsonl") << "{\"polycut_command_log\":1}\nnot json\n";
    options.commands = dir + "/bad.jsonl";
    EXPECT_THROW(record_offline(options, small_render(), sink), FileError);
    options.commands = "";
    options.max_frames = 0;
    EXPECT_THROW(record_offline(options, small_render(), sink), InputError);
    options.max_frames = 3; // no log: just step the scene
    EXPECT_EQ(record_offline(options, small_render(), sink).frames, 3);
}

} // namespace
} // namespace polycut::record

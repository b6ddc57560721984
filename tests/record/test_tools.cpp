// Small parts of polycut-record and polycut-bench: the command line, the progress bar line, the
// benchmark report's keys (the histogram figure: test_plot_bench.py).
#include "bench_report.hpp"
#include "polycut/common/error.hpp"
#include "progress_bar.hpp"
#include "record_options.hpp"
#include "test_support.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <set>

namespace polycut {
namespace {

TEST(RecordOptions, ParsesALiveRecording) {
    const auto c = record::parse_record_command({ "--server", "tcp://127.0.0.1:7000", "--every",
        "2", "--frames", "30", "--mp4", "out.mp4", "--size", "320x240", "--msaa", "0" });
    EXPECT_FALSE(c.offline);
    EXPECT_EQ(c.live.server, "tcp://127.0.0.1:7000");
    EXPECT_EQ(c.live.every, 2);
    EXPECT_EQ(c.live.max_frames, 30);
    EXPECT_EQ(c.mp4, "out.mp4");
    EXPECT_EQ(c.render.width, 320);
    EXPECT_EQ(c.render.height, 240);
    EXPECT_EQ(c.render.msaa, 0);
}

TEST(RecordOptions, ParsesAnOfflineRecording) {
    const auto c = record::parse_record_command(
        { "--offline", "scene.json", "--commands", "log.jsonl", "--png-dir", "frames" });
    EXPECT_TRUE(c.offline);
    EXPECT_EQ(c.offline_options.scene_file, "scene.json");
    EXPECT_EQ(c.offline_options.commands, "log.jsonl");
    EXPECT_EQ(c.png_dir, "frames");
    // A ParaView series alone is an output too.
    const auto v = record::parse_record_command({ "--offline", "scene.json", "--vtu", "steps" });
    EXPECT_EQ(v.offline_options.vtu_dir, "steps");
    EXPECT_TRUE(v.png_dir.empty() && v.mp4.empty());
}

TEST(RecordOptions, RejectsBadCommandLinesNamingTheOption) {
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        { { "--frames", "10" }, "--png-dir" }, // no output
        { { "--png-dir", "a", "--mp4", "b" }, "--png-dir" }, // both outputs
        { { "--png-dir", "a", "--every", "0" }, "--every" },
        { { "--png-dir", "a", "--frames", "2.5" }, "--frames" },
        { { "--png-dir", "a", "--size", "640" }, "--size" },
        { { "--png-dir", "a", "--frames", "3", "--seconds", "2" }, "--seconds" },
        { { "--png-dir", "a", "--commands", "log" }, "--commands" },
        { { "--png-dir", "a", "--bogus", "1" }, "--bogus" }, { { "--png-dir" }, "--png-dir" },
        { { "--png-dir", "a", "--vtu", "v" }, "--vtu" }, // the stream has no volume mesh
    };
    for (const auto& [args, option] : cases) {
        try {
            record::parse_record_command(args);
            ADD_FAILURE() << "accepted " << args.front();
        } catch (const InputError& e) {
            EXPECT_EQ(e.where(), option);
        }
    }
}

TEST(ProgressBar, LineShowsFractionCountsAndRate) {
    const std::string line = record::ProgressBar::line("rec", "ticks", 150, 600, 10.0);
    EXPECT_NE(line.find(" 25%"), std::string::npos) << line;
    EXPECT_NE(line.find("150/600 ticks"), std::string::npos) << line;
    EXPECT_NE(line.find("15.0/s"), std::string::npos) << line;
    EXPECT_NE(line.find("ETA 30 s"), std::string::npos) << line;
    EXPECT_NE(line.find("[#######.....................]"), std::string::npos) << line;
    const std::string done = record::ProgressBar::line("rec", "ticks", 600, 600, 10.0);
    EXPECT_NE(done.find("100%"), std::string::npos);
    EXPECT_EQ(done.find("ETA"), std::string::npos);
}

TEST(BenchReport, JsonHasTheDocumentedKeys) {
    bench::ProbeOptions options;
    bench::ProbeResult r;
    r.control_rtt_ms = { 0.3, 0.4, 0.5 };
    r.visible_ms = { 10, 12, 30 };
    r.visible_ticks = { 1, 1, 2 };
    r.step_ms = { 2, 3 };
    r.rate_hz = 60;
    const auto j = nlohmann::json::parse(bench::report_json(options, r));
    for (const char* key :
        { "machine", "config", "control_rtt_ms", "command_ack_ms", "command_to_visible_ms",
            "command_to_visible_ticks", "server", "stream", "commands" }) {
        EXPECT_TRUE(j.contains(key)) << key;
    }
    for (const char* key : { "count", "p50", "p95", "p99", "max", "mean" }) {
        EXPECT_TRUE(j["command_to_visible_ms"].contains(key)) << key;
    }
    EXPECT_EQ(j["command_to_visible_ms"]["count"], 3);
    EXPECT_DOUBLE_EQ(j["command_to_visible_ms"]["p50"].get<double>(), 12.0);
    EXPECT_DOUBLE_EQ(j["command_to_visible_ms"]["max"].get<double>(), 30.0);
    EXPECT_TRUE(j["server"].contains("step_ms"));
    EXPECT_TRUE(j["server"].contains("ticks_over_budget"));
    EXPECT_TRUE(j["machine"].contains("logical_cpus"));
    // The raw samples the matplotlib histograms are drawn from, as measured.
    EXPECT_EQ(j["samples"]["command_to_visible_ms"], nlohmann::json({ 10.0, 12.0, 30.0 }));
    EXPECT_EQ(j["samples"]["control_rtt_ms"].size(), 3u);
    EXPECT_EQ(j["samples"]["server_step_ms"].size(), 2u);
}

} // namespace
} // namespace polycut

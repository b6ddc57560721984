// Frame sinks and the fixed-camera recorder: the mp4 path (ffprobe counts the frames and reads
// the size), the PNG directory, and clear errors when ffmpeg is missing or dies.
#include "frame_recorder.hpp"
#include "polycut/common/error.hpp"
#include "test_support.hpp"

#include <filesystem>
#include <gtest/gtest.h>

namespace polycut::record {
namespace {

using test::make_box;

/// Renders `frames` frames of a box that grows taller, into `sink`.
void record_box(FrameRecorder& recorder, int frames) {
    for (int k = 0; k < frames; ++k) {
        const test::BoxSurface box = make_box(0.1, 0.08, 0.03 + 0.002 * k);
        recorder.add(box.arrays());
    }
    recorder.finish();
}

TEST(Mp4Sink, FfprobeCountsEveryFrameAtTheRequestedSize) {
    if (find_executable("ffmpeg").empty() || find_executable("ffprobe").empty()) {
        GTEST_SKIP() << "ffmpeg/ffprobe not installed";
    }
    const std::string dir = test::scratch_dir("mp4");
    Mp4Options mp4;
    mp4.path = dir + "/box.mp4";
    mp4.width = 320;
    mp4.height = 240;
    mp4.fps = 30;
    RecordRender settings;
    settings.width = 320;
    settings.height = 240;
    settings.msaa = 0;
    FrameRecorder recorder(settings, make_mp4_sink(mp4));
    constexpr int kFrames = 17;
    record_box(recorder, kFrames);
    EXPECT_EQ(recorder.frames(), kFrames);

    const auto info = test::probe_video(mp4.path);
    ASSERT_FALSE(info.empty()) << "ffprobe could not read " << mp4.path;
    EXPECT_EQ(info.at("width"), "320");
    EXPECT_EQ(info.at("height"), "240");
    EXPECT_EQ(info.at("nb_read_frames"), std::to_string(kFrames));
    EXPECT_TRUE(info.at("codec_name") == "h264" || info.at("codec_name") == "mpeg4")
        << info.at("codec_name");
}

TEST(Mp4Sink, MissingFfmpegIsAClearError) {
    Mp4Options mp4;
    mp4.path = test::scratch_dir("mp4_missing") + "/x.mp4";
    mp4.ffmpeg = "/nonexistent/ffmpeg";
    try {
        make_mp4_sink(mp4);
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("not found"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("apt-get install ffmpeg"), std::string::npos);
    }
}

TEST(Mp4Sink, OddSizeIsRejectedBeforeStarting) {
    Mp4Options mp4;
    mp4.path = test::scratch_dir("mp4_odd") + "/x.mp4";
    mp4.width = 321;
    EXPECT_THROW(make_mp4_sink(mp4), InputError);
}

TEST(Mp4Sink, EncoderThatExitsIsReportedNotASigpipe) {
    // /bin/false stands in for an ffmpeg that dies at once: the writes hit a closed pipe.
    if (find_executable("/bin/false").empty()) {
        GTEST_SKIP() << "/bin/false missing";
    }
    Mp4Options mp4;
    mp4.path = test::scratch_dir("mp4_dies") + "/x.mp4";
    mp4.width = 640;
    mp4.height = 480;
    mp4.ffmpeg = "/bin/false";
    auto sink = make_mp4_sink(mp4);
    render::Image frame;
    frame.width = 640;
    frame.height = 480;
    frame.rgba.assign(640 * 480 * 4, 128);
    try {
        for (int k = 0; k < 8; ++k) {
            sink->write(k, frame); // 1.2 MB each: more than a pipe buffer
        }
        sink->finish();
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("exited with status 1"), std::string::npos)
            << e.what();
    }
}

TEST(PngSink, WritesOneNumberedFilePerFrame) {
    const std::string dir = test::scratch_dir("png") + "/frames";
    RecordRender settings;
    settings.width = 160;
    settings.height = 120;
    settings.msaa = 0;
    settings.stills_dir = test::scratch_dir("png_stills");
    settings.still_every = 4;
    FrameRecorder recorder(settings, make_png_sink(dir));
    record_box(recorder, 9);
    long files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        files += entry.path().extension() == ".png" ? 1 : 0;
    }
    EXPECT_EQ(files, 9);
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + png_frame_name(0)));
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + png_frame_name(8)));
    const render::Image first = render::read_png(dir + "/" + png_frame_name(0));
    EXPECT_EQ(first.width, 160);
    EXPECT_EQ(first.height, 120);
    // Stills: frames 0, 4, 8.
    long stills = 0;
    for (const auto& entry : std::filesystem::directory_iterator(settings.stills_dir)) {
        stills += entry.path().extension() == ".png" ? 1 : 0;
    }
    EXPECT_EQ(stills, 3);
}

TEST(FrameRecorder, CameraIsFixedByTheFirstFrame) {
    RecordRender settings;
    settings.width = 160;
    settings.height = 120;
    settings.msaa = 0;
    FrameRecorder recorder(settings, make_png_sink(test::scratch_dir("camera")));
    const test::BoxSurface small = make_box(0.1, 0.1, 0.05);
    recorder.add(small.arrays());
    const render::Camera first = *recorder.camera();
    const test::BoxSurface big = make_box(0.3, 0.3, 0.2);
    recorder.add(big.arrays());
    EXPECT_TRUE(recorder.camera()->position.isApprox(first.position, 0.0));
    EXPECT_TRUE(recorder.camera()->target.isApprox(first.target, 0.0));
}

TEST(FrameRecorder, CutTaggedFacesShowTheCutColour) {
    RecordRender settings;
    settings.width = 160;
    settings.height = 120;
    settings.msaa = 0;
    FrameRecorder recorder(settings, make_png_sink(test::scratch_dir("cut_colour")));
    const test::BoxSurface skin = make_box(0.1, 0.1, 0.05, 1);
    recorder.add(skin.arrays());
    EXPECT_EQ(test::count_cut_pixels(recorder.last_image()), 0);
    const test::BoxSurface cut = make_box(0.1, 0.1, 0.05, 2);
    recorder.add(cut.arrays());
    EXPECT_GT(test::count_cut_pixels(recorder.last_image()), 160 * 120 / 20);
}

} // namespace
} // namespace polycut::record

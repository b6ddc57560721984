// Shared helpers of the mesh file tests: the data directory and a scratch directory per test.
#pragma once

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <sstream>
#include <string>

namespace polycut::test {

namespace fs = std::filesystem;

inline const std::string kData = POLYCUT_SOURCE_DIR "/tests/mesh/data/";

/// A fresh directory for the running test's files.
inline fs::path test_dir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    fs::path dir = fs::path(POLYCUT_BINARY_DIR) / "tests" / "mesh" / "io_tmp"
        / (std::string(info->test_suite_name()) + "." + info->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

inline void write_text(const fs::path& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

inline std::string read_text(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

} // namespace polycut::test

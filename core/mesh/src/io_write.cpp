// Number formatting and all-or-nothing file output for the writers.
#include "io_write.hpp"

#include "polycut/common/error.hpp"

#include <array>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace polycut::mesh::io {

void append_number(std::string& out, double v) {
    std::array<char, 32> buf {};
    const auto [ptr, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    out.append(buf.data(), ec == std::errc() ? ptr : buf.data());
}

void append_number(std::string& out, long v) {
    std::array<char, 24> buf {};
    const auto [ptr, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    out.append(buf.data(), ec == std::errc() ? ptr : buf.data());
}

void write_file(const std::string& path, const std::string& content) {
    const std::string part = path + ".part";
    {
        std::ofstream out(part, std::ios::binary | std::ios::trunc);
        if (!out)
            throw FileError(
                path, 0, std::string("cannot open for writing: ") + std::strerror(errno));
        out.write(content.data(), std::streamsize(content.size()));
        out.flush();
        if (!out) {
            const std::string why = std::strerror(errno);
            out.close();
            std::remove(part.c_str());
            throw FileError(path, 0, "write failed: " + why);
        }
    }
    std::error_code ec;
    std::filesystem::rename(part, path, ec);
    if (ec) {
        std::remove(part.c_str());
        throw FileError(path, 0, "cannot rename the written file into place: " + ec.message());
    }
}

} // namespace polycut::mesh::io

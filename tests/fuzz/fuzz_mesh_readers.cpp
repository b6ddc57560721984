// libFuzzer target: the volume mesh readers, gmsh .msh and TetGen .node/.ele (issue 14 item 6).
// Byte 0 picks the reader; for TetGen the rest is split at the first "@@" into the two files.
// A reader must return a mesh or throw polycut::Error (FileError / MeshError), nothing else.
#include "polycut/common/error.hpp"
#include "polycut/mesh/io.hpp"

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) {
        return 0;
    }
    const std::string body(reinterpret_cast<const char*>(data + 1), size - 1);
    const auto base = std::filesystem::temp_directory_path()
        / ("polycut_fuzz_mesh_" + std::to_string(::getpid()));
    std::string path;
    if (data[0] % 2 == 0) {
        path = base.string() + ".msh";
        std::ofstream(path, std::ios::binary) << body;
    } else {
        const auto split = body.find("@@");
        std::ofstream(base.string() + ".node", std::ios::binary) << body.substr(0, split);
        std::ofstream(base.string() + ".ele", std::ios::binary)
            << (split == std::string::npos ? std::string() : body.substr(split + 2));
        path = base.string() + ".node";
    }
    try {
        (void)polycut::mesh::read_volume_mesh(path);
    } catch (const polycut::Error&) {
    } catch (...) {
        std::abort();
    }
    return 0;
}

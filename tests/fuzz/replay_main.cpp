// Replays libFuzzer corpora without libFuzzer (g++ builds, every ./polycut test): calls the
// target on every file of the directories given, and on every file given itself (as a libFuzzer
// binary takes a crash file). Exit status 0 when every input ran; 2 on a path that is neither.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

void replay(const std::filesystem::path& file) {
    if (std::getenv("POLYCUT_REPLAY_VERBOSE") != nullptr) {
        std::fprintf(stderr, "input %s\n", file.c_str()); // names a crash
    }
    std::ifstream in(file, std::ios::binary);
    const std::vector<char> bytes(
        (std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

} // namespace

int main(int argc, char** argv) {
    std::size_t inputs = 0;
    for (int a = 1; a < argc; ++a) {
        const std::filesystem::path path(argv[a]);
        std::error_code ec;
        if (std::filesystem::is_regular_file(path, ec)) {
            replay(path);
            ++inputs;
            continue;
        }
        if (!std::filesystem::is_directory(path, ec)) {
            std::fprintf(stderr, "%s: neither a file nor a directory\n", argv[a]);
            return 2;
        }
        for (const auto& entry : std::filesystem::directory_iterator(path)) {
            if (entry.is_regular_file()) {
                replay(entry.path());
                ++inputs;
            }
        }
    }
    std::printf("replayed %zu inputs\n", inputs);
    return inputs > 0 ? 0 : 1;
}

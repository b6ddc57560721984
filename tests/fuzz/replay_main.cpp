// Replays libFuzzer corpora without libFuzzer (g++ builds, every ./polycut test): calls the
// target on every file of the directories given. Exit status 0 when every input ran.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

int main(int argc, char** argv) {
    std::size_t inputs = 0;
    for (int a = 1; a < argc; ++a) {
        for (const auto& entry : std::filesystem::directory_iterator(argv[a])) {
            if (!entry.is_regular_file()) {
                continue;
            }
            if (std::getenv("POLYCUT_REPLAY_VERBOSE") != nullptr) {
                std::fprintf(stderr, "input %s\n", entry.path().c_str()); // names a crash
            }
            std::ifstream in(entry.path(), std::ios::binary);
            const std::vector<char> bytes(
                (std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            LLVMFuzzerTestOneInput(
                reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
            ++inputs;
        }
    }
    std::printf("replayed %zu inputs\n", inputs);
    return inputs > 0 ? 0 : 1;
}

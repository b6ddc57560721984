// libFuzzer target: the scene parser (issue 14 item 6). Any text must give a Scene or a
// polycut::Error (SceneError naming the field); nothing else may escape, nothing may crash.
#include "polycut/common/error.hpp"
#include "polycut/scene/scene.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        (void)polycut::scene::parse_scene(text, "/nonexistent-scene-dir");
    } catch (const polycut::Error&) {
        // the documented outcome for bad input
    } catch (const std::exception& e) {
        std::fprintf(stderr, "parse_scene threw a non-polycut exception: %s\n", e.what());
        std::abort();
    } catch (...) {
        std::abort();
    }
    return 0;
}

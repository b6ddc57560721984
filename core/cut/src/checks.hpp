// Self-checks of the cutter's incremental structures (the undo journal's mirrors, the snap
// cutter's cached tet volumes and cell grid): each is compared with what a full recomputation
// gives. On in debug builds and with the environment variable POLYCUT_CHECK_UNDO=1 (set for
// every GoogleTest case by CMakeLists.txt); off otherwise, since a check costs O(mesh).
#pragma once

#include <cstdlib>

namespace polycut::cut::detail {

inline bool incremental_checks() {
#ifndef NDEBUG
    return true;
#else
    const char* v = std::getenv("POLYCUT_CHECK_UNDO");
    return v != nullptr && v[0] != '\0' && v[0] != '0';
#endif
}

} // namespace polycut::cut::detail

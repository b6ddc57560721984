# Warnings for the project's own code only (dependencies are included as SYSTEM).
add_library(polycut_warnings INTERFACE)
target_compile_options(polycut_warnings INTERFACE
    -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual
    -Wnull-dereference -Wimplicit-fallthrough
    $<$<BOOL:${POLYCUT_WERROR}>:-Werror>)
if(POLYCUT_SANITIZE)
    target_compile_options(polycut_warnings INTERFACE
        -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
    target_link_options(polycut_warnings INTERFACE -fsanitize=address,undefined)
endif()
